"""The IOC's forward problem as a differentiable NLP (``problem.forward``; docs/differentiable.md).

Under the model and task the IOC believes in, the forward problem for unit weights ``w``
over the problem's features is::

    min_x  s * w . phi(x) + R(x)    s.t.   lbg <= g(x) <= ubg,   lbx <= x <= ubx

with ``s`` = :attr:`ForwardView.objective_scale` and ``R`` the weight-independent knee-lock
penalty. This view gives, at any decision vector ``x``: the map to and from trajectories,
constraint values, bounds and the sparse constraint Jacobian, each feature's value,
gradient and Hessian (in the problem's feature order), ``R`` and its gradient, the
Lagrangian's Hessian, the active set; and at an oracle solution its duals and the
sensitivity ``dx*/dw`` from the KKT system. Inverse-KKT, implicit-gradient bilevel and
single-level methods are written with these (see ``ioc_bench/ioc/inverse_kkt.py``).

Every call is counted and timed in the problem's :attr:`~IOCProblem.stats` (``"derivatives"``
for values and derivatives at a point, ``"sensitivity"`` for the KKT solve).
"""

from __future__ import annotations

from functools import cached_property
from typing import TYPE_CHECKING

import numpy as np
import scipy.sparse as sp

from ioc_bench.trajectory import Trajectory
from ioc_bench.trajopt.derivatives import ActiveSet, StepDerivatives
from ioc_bench.trajopt.step_problem import OBJECTIVE_SCALE, StepRules
from ioc_bench.weights import full_weights

if TYPE_CHECKING:
    from ioc_bench.ioc.problem import IOCProblem, OracleSolution


class ForwardView:
    """Values and derivatives of an :class:`IOCProblem`'s forward problem."""

    def __init__(self, problem: IOCProblem):
        self._problem = problem
        self._solver = problem._solver
        self._d = StepDerivatives(self._solver)
        nlp = self._solver.nlp
        self._columns = [nlp.features.index(f) for f in problem.features]
        self.features: tuple[str, ...] = problem.features
        self.objective_scale: float = OBJECTIVE_SCALE
        self.n_x: int = nlp.layout.size
        self.n_g: int = len(nlp.constraints.lb)

    # -- the map between trajectories and decision vectors -------------------------------------
    def vector(self, trajectory: Trajectory) -> np.ndarray:
        """The decision vector of a full trajectory."""
        return self._solver.decision_vector(trajectory)

    def trajectory(self, x: np.ndarray) -> Trajectory:
        """The trajectory a decision vector encodes."""
        return self._solver.trajectory(np.asarray(x, dtype=float), self._p(np.zeros(self._problem.n_features)))

    @property
    def blocks(self) -> dict[str, slice]:
        """Where each named block (``dt``, ``q``, ``v``, ``force``, ``tau``, ...) sits in ``x``."""
        layout = self._solver.nlp.layout
        return {name: layout.slice(name) for name in layout.blocks}

    @property
    def constraint_groups(self) -> dict[str, slice]:
        """Where each named constraint group (``collocation``, ``pin_position``, ...) sits in ``g``."""
        return dict(self._solver.nlp.constraints.groups)

    @cached_property
    def _bounds(self) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        p = self._problem
        nlp = self._solver.nlp
        return (*nlp.variable_bounds(p.params), *nlp.constraint_bounds(p.task.step_length, StepRules()))

    def variable_bounds(self) -> tuple[np.ndarray, np.ndarray]:
        """(lbx, ubx)."""
        return self._bounds[0].copy(), self._bounds[1].copy()

    def constraint_bounds(self) -> tuple[np.ndarray, np.ndarray]:
        """(lbg, ubg); equality constraints have lbg == ubg."""
        return self._bounds[2].copy(), self._bounds[3].copy()

    # -- values and derivatives at a point -------------------------------------------------------
    def constraints(self, x: np.ndarray) -> np.ndarray:
        """(n_g,) constraint values g(x)."""
        with self._timed():
            return self._d.constraints(x, self._p())

    def constraint_jacobian(self, x: np.ndarray) -> sp.csc_matrix:
        """(n_g, n_x) sparse Jacobian of g."""
        with self._timed():
            return self._d.constraint_jacobian(x, self._p())

    def features_at(self, x: np.ndarray) -> np.ndarray:
        """(F,) the problem's features at x."""
        with self._timed():
            return self._d.features(x, self._p())[self._columns]

    def feature_jacobian(self, x: np.ndarray) -> sp.csc_matrix:
        """(F, n_x) sparse gradients of the problem's features (rows in feature order)."""
        with self._timed():
            return self._d.feature_jacobian(x, self._p())[self._columns]

    def feature_hessian(self, x: np.ndarray, feature: str) -> sp.csc_matrix:
        """(n_x, n_x) sparse Hessian of one feature."""
        index = self._solver.nlp.features.index(feature)
        with self._timed():
            return self._d.feature_hessian(x, self._p(), index)

    def regularizer(self, x: np.ndarray) -> float:
        """R(x): the weight-independent objective term (the knee-lock penalty)."""
        with self._timed():
            return self._d.regularizer(x, self._p())

    def regularizer_gradient(self, x: np.ndarray) -> np.ndarray:
        """(n_x,) gradient of R."""
        with self._timed():
            return self._d.regularizer_gradient(x, self._p())

    def lagrangian_hessian(self, x: np.ndarray, weights: np.ndarray, lam_g: np.ndarray) -> sp.csc_matrix:
        """(n_x, n_x) Hessian of ``s w . phi + R + lam_g . g`` for unit ``weights``."""
        with self._timed():
            return self._d.lagrangian_hessian(x, self._p(weights), lam_g)

    def active_set(self, x: np.ndarray, tol: float = 1e-7) -> ActiveSet:
        """Equality constraints, active inequalities and variables at a bound, at x."""
        with self._timed():
            return self._d.active_set(x, self._d.constraints(x, self._p()), self._bounds, tol)

    # -- at an oracle solution ---------------------------------------------------------------------
    def duals(self, solution: OracleSolution) -> tuple[np.ndarray, np.ndarray]:
        """(lam_g, lam_x): the solution's multipliers, in IPOPT's sign convention (the
        stationarity is ``grad f + J_g^T lam_g + lam_x = 0``; a multiplier is >= 0 on an
        active upper bound and <= 0 on an active lower one)."""
        s = _solve(solution)
        return s.lam_g.copy(), s.lam_x.copy()

    def sensitivity(self, solution: OracleSolution) -> np.ndarray:
        """(n_x, F) derivative of the optimum by the weights, at an ``optimize`` solution.

        From the KKT system with the solution's active set held fixed (implicit-function
        theorem). The weights are used as given (``optimize`` normalises them to unit norm,
        so a step along ``w`` itself changes nothing: compose with that projection).
        """
        s = _solve(solution)
        if solution.weights.size != self._problem.n_features or not np.any(solution.weights):
            raise ValueError("sensitivity needs a solution of optimize(weights), not of project()")
        p = self._p(solution.weights)
        with self._problem.stats.timed("sensitivity"):
            active = self._d.active_set(s.x, self._d.constraints(s.x, p), self._bounds)
            dx = self._d.sensitivity(s.x, p, s.lam_g, active)
        return dx[:, self._columns]

    # -- internals ----------------------------------------------------------------------------------
    def _p(self, weights: np.ndarray | None = None) -> np.ndarray:
        prob = self._problem
        w = np.zeros(prob.n_features) if weights is None else np.asarray(weights, dtype=float)
        full = full_weights(w, prob.features, self._solver.nlp.features)
        return self._solver.nlp.parameter_vector(prob.params, prob.task.speed, full, rules=StepRules())

    def _timed(self):
        return self._problem.stats.timed("derivatives")


def _solve(solution: OracleSolution):
    if solution._solve is None:
        raise ValueError("this solution carries no solver data (it was not returned by an oracle)")
    return solution._solve
