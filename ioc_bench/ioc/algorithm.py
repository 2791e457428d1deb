"""The IOC algorithm interface: a name, a config and ``fit(problem) -> IOCResult``."""

from __future__ import annotations

from dataclasses import asdict, dataclass, field, is_dataclass
from typing import Any, ClassVar

import numpy as np

from ioc_bench.ioc.problem import IOCProblem


@dataclass(frozen=True)
class IterationRecord:
    """One iteration of an iterative IOC method: a candidate and its optimal step.

    Attributes:
        weights: (F,) candidate weights (unit norm).
        tracking_error: :meth:`IOCProblem.tracking_error` of the candidate's step (positions,
            velocities and torques, span-normalised), NaN if its solve failed.
        trajectory_error: the paper's :meth:`IOCProblem.trajectory_error` of that step
            (segment angles and angular velocities), NaN if its solve failed.
        solve_status: status of the candidate's forward solve.
        extra: algorithm-specific numbers for this iteration (e.g. a cutting-plane method's
            ``cost_gap``), shown as they are.
    """

    weights: tuple[float, ...]
    tracking_error: float
    trajectory_error: float
    solve_status: str = ""
    extra: dict[str, Any] = field(default_factory=dict)

    def to_dict(self) -> dict[str, Any]:
        return asdict(self)

    @classmethod
    def of(cls, problem: IOCProblem, weights: np.ndarray, solution: Any, **extra: Any) -> IterationRecord:
        """The record of candidate ``weights`` and its oracle ``solution``."""
        ok = bool(solution.success)
        return cls(
            weights=tuple(float(x) for x in weights),
            tracking_error=problem.tracking_error(solution.trajectory) if ok else float("nan"),
            trajectory_error=problem.trajectory_error(solution.trajectory) if ok else float("nan"),
            solve_status=str(solution.status),
            extra=extra,
        )


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
    #: The method family (e.g. ``cutting-plane``, ``inverse-kkt``, ``bilevel``, ``single-level``).
    family: ClassVar[str] = "other"
    Config: ClassVar[type] = type(None)

    def __init__(self, config: Any = None, **overrides: Any):
        if config is None:
            config = self.Config(**overrides) if self.Config is not type(None) else None
        elif overrides:
            raise TypeError("pass either a config object or keyword overrides, not both")
        self.config = config

    def fit(self, problem: IOCProblem) -> IOCResult:
        raise NotImplementedError

    @classmethod
    def prepare(cls) -> None:
        """Build what every case of this algorithm shares (e.g. a compiled NLP), once per
        process; the runner calls it before forking workers. Default: nothing."""

    def config_dict(self) -> dict[str, Any]:
        return asdict(self.config) if is_dataclass(self.config) else {}
