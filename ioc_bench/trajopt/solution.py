"""What a forward solve starts from and what it returns.

A :class:`StartPoint` is a primal point and, for a warm start, its multipliers. A
:class:`SolveResult` is the step found, its primal-dual point and a :class:`SolverReport`
saying whether it is valid: IPOPT converged, every constraint and bound holds to
:data:`FEASIBILITY_TOL` and the knee-lock complementarity to ``LOCK_TOL``. A failed solve is
a result, never an exception.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass
from typing import Any

import numpy as np

from ioc_bench.trajectory import Trajectory
from ioc_bench.trajopt.ipopt import converged

#: A solution is feasible when IPOPT converged and no constraint or bound is violated by more.
FEASIBILITY_TOL = 1e-6


@dataclass(frozen=True)
class SolverReport:
    """How one IPOPT run went.

    Attributes:
        status: IPOPT's return status, e.g. ``Solve_Succeeded``.
        success: IPOPT converged and the solution is feasible (see :attr:`feasible`).
        max_violation: largest constraint or bound violation at the returned point.
        complementarity: largest knee-lock complementarity product (valid: <= LOCK_TOL).
        iterations: IPOPT iterations.
        wall_time: seconds spent in the solve.
        objective: the weighted cost ``w . phi`` at the returned point (the effort term of
            the objective, without tracking or lock penalty).
        warm: whether the solve was warm-started.
        repaired: whether a complementarity repair re-solve was needed (see
            :meth:`~ioc_bench.trajopt.forward_problem.ForwardProblem.solve`).
    """

    status: str
    success: bool
    max_violation: float
    complementarity: float
    iterations: int
    wall_time: float
    objective: float
    warm: bool = False
    repaired: bool = False

    @property
    def converged(self) -> bool:
        """IPOPT reported convergence (to its tolerances or acceptable ones)."""
        return converged(self.status)

    def to_dict(self) -> dict[str, Any]:
        return asdict(self)


@dataclass(frozen=True, eq=False)
class StartPoint:
    """Where a solve starts: a primal point and, for a warm start, its multipliers."""

    x: np.ndarray
    lam_x: np.ndarray | None = None
    lam_g: np.ndarray | None = None

    @property
    def warm(self) -> bool:
        return self.lam_x is not None and self.lam_g is not None


@dataclass(frozen=True, eq=False)
class SolveResult:
    """A solve's trajectory and report, plus the primal-dual point for warm starts."""

    trajectory: Trajectory
    report: SolverReport
    x: np.ndarray
    lam_x: np.ndarray
    lam_g: np.ndarray

    @property
    def point(self) -> StartPoint:
        """The solution as a warm start (its primal-dual point)."""
        return StartPoint(self.x, self.lam_x, self.lam_g)
