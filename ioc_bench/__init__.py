"""ioc-bench: a benchmark for inverse optimal control of bipedal walking.

The forward problem (optimal gaits of a 5-segment planar walker) after Rebula, Schaal,
Finley & Righetti, "A Robustness Analysis of Inverse Optimal Control of Bipedal Walking".
"""

from ioc_bench._version import __version__
from ioc_bench.bench.case import CaseResult, run_case
from ioc_bench.bench.conditions import CONDITIONS, Condition
from ioc_bench.demo import Demonstration, DemonstrationFileError
from ioc_bench.features import ALL_FEATURES, COST_FEATURES, DISTRACTORS, FEATURES
from ioc_bench.ioc import (
    API_VERSION,
    IOCAlgorithm,
    IOCProblem,
    IOCResult,
    IterationRecord,
    ModelFit,
    OracleSolution,
    WeightRegion,
    algorithms,
    make_algorithm,
    register_algorithm,
)
from ioc_bench.model.params import SegmentParams, WalkerParams
from ioc_bench.optimize import optimize_gait
from ioc_bench.task import Task
from ioc_bench.weights import WEIGHT_SETS, parse_weights

__all__ = [
    "ALL_FEATURES",
    "API_VERSION",
    "CONDITIONS",
    "COST_FEATURES",
    "DISTRACTORS",
    "FEATURES",
    "WEIGHT_SETS",
    "CaseResult",
    "Condition",
    "Demonstration",
    "DemonstrationFileError",
    "IOCAlgorithm",
    "IOCProblem",
    "IOCResult",
    "IterationRecord",
    "ModelFit",
    "OracleSolution",
    "SegmentParams",
    "Task",
    "WalkerParams",
    "WeightRegion",
    "__version__",
    "algorithms",
    "make_algorithm",
    "optimize_gait",
    "parse_weights",
    "register_algorithm",
    "run_case",
]
