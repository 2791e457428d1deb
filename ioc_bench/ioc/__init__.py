"""Inverse optimal control: the problem, the algorithm interface, the registry."""

from ioc_bench.ioc.algorithm import (
    API_VERSION,
    FAMILIES,
    IOCAlgorithm,
    IOCResult,
    IterationRecord,
    ModelFit,
    WeightRegion,
)
from ioc_bench.ioc.oracle import OracleSolution
from ioc_bench.ioc.problem import IOCProblem
from ioc_bench.ioc.registry import (
    AlgorithmError,
    algorithms,
    describe_algorithms,
    get_algorithm,
    make_algorithm,
    register_algorithm,
)

__all__ = [
    "API_VERSION",
    "FAMILIES",
    "AlgorithmError",
    "IOCAlgorithm",
    "IOCProblem",
    "IOCResult",
    "IterationRecord",
    "ModelFit",
    "OracleSolution",
    "WeightRegion",
    "algorithms",
    "describe_algorithms",
    "get_algorithm",
    "make_algorithm",
    "register_algorithm",
]
