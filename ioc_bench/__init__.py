"""ioc-bench: a benchmark for inverse optimal control of bipedal walking.

The forward problem (optimal gaits of a 5-segment planar walker) after Rebula, Schaal,
Finley & Righetti, "A Robustness Analysis of Inverse Optimal Control of Bipedal Walking".
"""

from ioc_bench.demo import Demonstration, DemonstrationFileError
from ioc_bench.features import ALL_FEATURES, COST_FEATURES, DISTRACTORS, FEATURES
from ioc_bench.model.params import SegmentParams, WalkerParams
from ioc_bench.optimize import optimize_gait
from ioc_bench.task import Task
from ioc_bench.weights import WEIGHT_SETS, parse_weights

__version__ = "0.1.0"

__all__ = [
    "ALL_FEATURES",
    "COST_FEATURES",
    "DISTRACTORS",
    "FEATURES",
    "WEIGHT_SETS",
    "Demonstration",
    "DemonstrationFileError",
    "SegmentParams",
    "Task",
    "WalkerParams",
    "optimize_gait",
    "parse_weights",
]
