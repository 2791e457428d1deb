"""The IOC algorithm interface: a name, a config and ``fit(problem) -> IOCResult``."""

from __future__ import annotations

from dataclasses import asdict, dataclass, field, is_dataclass
from typing import Any, ClassVar

import numpy as np

from ioc_bench.ioc.problem import IOCProblem


@dataclass(frozen=True)
class IterationRecord:
    """One iteration of an iterative IOC method.

    Attributes:
        weights: (F,) candidate weights (unit norm).
        trajectory_error: error of the candidate's optimal step to the observation
            (:meth:`IOCProblem.trajectory_error`), NaN if the solve failed.
        solve_status: status of the candidate's forward solve.
        cost_gap: ``w . (phi(x_w) - phi(x*))`` relative to ``w . phi(x*)``: negative when
            the new step is cheaper than the observation under the candidate, i.e. the new
            sample cuts the candidate off; >= 0 means it adds no information.
        extra: algorithm-specific numbers for this iteration.
    """

    weights: tuple[float, ...]
    trajectory_error: float
    solve_status: str = ""
    cost_gap: float = float("nan")
    extra: dict[str, Any] = field(default_factory=dict)

    @property
    def cuts(self) -> bool:
        return bool(self.cost_gap < 0)

    def to_dict(self) -> dict[str, Any]:
        return asdict(self)


@dataclass(frozen=True)
class IOCResult:
    """What an algorithm returns.

    Attributes:
        weights: (F,) estimated weights over the problem's features (non-negative).
        status: ``converged``, ``max_iterations``, ``infeasible`` (stopped because no
            weights separate the samples), or ``failed: <reason>``.
        history: per-iteration records (may be empty for non-iterative methods).
        chosen_iteration: index into ``history`` of the output, if any.
        notes: free-form numbers or text the algorithm wants in the record.
    """

    weights: np.ndarray
    status: str = "converged"
    history: tuple[IterationRecord, ...] = ()
    chosen_iteration: int | None = None
    notes: dict[str, Any] = field(default_factory=dict)


class IOCAlgorithm:
    """Base class of IOC algorithms.

    Subclasses set ``Config`` (a frozen dataclass with documented defaults) and
    ``description`` (one line), and implement :meth:`fit`. Register them with
    :func:`ioc_bench.register_algorithm`.
    """

    name: ClassVar[str] = ""
    description: ClassVar[str] = ""
    Config: ClassVar[type] = type(None)

    def __init__(self, config: Any = None, **overrides: Any):
        if config is None:
            config = self.Config(**overrides) if self.Config is not type(None) else None
        elif overrides:
            raise TypeError("pass either a config object or keyword overrides, not both")
        self.config = config

    def fit(self, problem: IOCProblem) -> IOCResult:
        raise NotImplementedError

    def config_dict(self) -> dict[str, Any]:
        return asdict(self.config) if is_dataclass(self.config) else {}
