"""What an IOC problem's oracles return, and how their calls are counted.

An :class:`OracleSolution` is a step an oracle (``optimize``, ``project``) returned, with its
features under the problem's feature set and, for a solve, its primal-dual point (what a
warm start and the differentiable view read). :class:`OracleStats` counts every oracle and
derivative call and the seconds it took.
"""

from __future__ import annotations

import time
from collections import Counter
from dataclasses import dataclass, field

import numpy as np

from ioc_bench.trajectory import Trajectory
from ioc_bench.trajopt.solution import SolverReport, StartPoint


@dataclass(frozen=True, eq=False)
class OracleSolution:
    """A step returned by an oracle.

    Attributes:
        trajectory: the step (a full trajectory: pin forces, lock torques, impulses too).
        features: (F,) its feature values, in the problem's feature order.
        success: the solve converged to a feasible point.
        status: the solver's status string.
        objective: ``w . phi`` at the solution for ``optimize`` (0 for ``project``).
        weights: (F,) the unit weights it was optimal for (zeros for a projection).
        point: the solve's primal-dual point (``x``, ``lam_x``, ``lam_g``; what a warm start
            from this solution begins at), None for a solution not made by a solve.
        report: the solve's full report (iterations, wall time, violation), or None.
    """

    trajectory: Trajectory
    features: np.ndarray
    success: bool
    status: str
    objective: float
    weights: np.ndarray = field(default_factory=lambda: np.zeros(0))
    point: StartPoint | None = field(default=None, repr=False)
    report: SolverReport | None = field(default=None, repr=False)


@dataclass
class OracleStats:
    """Calls and seconds spent per oracle."""

    calls: Counter = field(default_factory=Counter)
    seconds: Counter = field(default_factory=Counter)

    @property
    def forward_solves(self) -> int:
        """Trajectory optimizations of any kind (``optimize`` and ``project``)."""
        return self.calls["optimize"] + self.calls["project"]

    def to_dict(self) -> dict:
        return {"calls": dict(self.calls), "seconds": dict(self.seconds), "forward_solves": self.forward_solves}

    def copy(self) -> OracleStats:
        return OracleStats(Counter(self.calls), Counter(self.seconds))

    def timed(self, name: str) -> _Timer:
        """A context manager counting one call of ``name`` and its time."""
        return _Timer(self, name)


class _Timer:
    def __init__(self, stats: OracleStats, name: str):
        self.stats, self.name = stats, name

    def __enter__(self) -> None:
        self.t0 = time.perf_counter()

    def __exit__(self, *exc: object) -> None:
        self.stats.calls[self.name] += 1
        self.stats.seconds[self.name] += time.perf_counter() - self.t0
