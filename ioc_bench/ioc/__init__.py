"""Inverse optimal control: the problem, the algorithm interface, the registry."""

from ioc_bench.ioc.algorithm import IOCAlgorithm, IOCResult, IterationRecord
from ioc_bench.ioc.problem import IOCProblem, OracleSolution
from ioc_bench.ioc.registry import (
    AlgorithmError,
    algorithms,
    describe_algorithms,
    get_algorithm,
    make_algorithm,
    register_algorithm,
)

__all__ = [
    "AlgorithmError",
    "IOCAlgorithm",
    "IOCProblem",
    "IOCResult",
    "IterationRecord",
    "OracleSolution",
    "algorithms",
    "describe_algorithms",
    "get_algorithm",
    "make_algorithm",
    "register_algorithm",
]
