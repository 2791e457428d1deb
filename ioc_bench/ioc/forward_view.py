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
from ioc_bench.trajopt.step_problem import OBJECTIVE_SCALE, StepRules, SymbolicStep
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

    @cached_property
    def signal_indices(self) -> np.ndarray:
        """(T, n) index into ``x`` of every signal of :meth:`Observation.signals` (positions,
        velocities and torques knot by knot), so that ``x[signal_indices]`` are the signals."""
        layout = self._solver.nlp.layout
        t = self._solver.nlp.n_knots
        index = np.arange(layout.size)
        parts = [index[layout.slice(name)].reshape(t, -1) for name in ("q", "v", "tau")]
        return np.concatenate(parts, axis=1)

    def tracking_error(self, x: np.ndarray) -> tuple[float, np.ndarray]:
        """:meth:`IOCProblem.tracking_error` of the step ``x`` encodes, and its gradient in ``x``."""
        prob = self._problem
        idx = self.signal_indices
        observed = prob.observed.signals(len(self._solver.nlp.actuators))
        measured = np.isfinite(observed)
        diff = np.where(measured, (x[idx] - np.where(measured, observed, 0.0)) / prob.signal_spans, 0.0)
        n = max(int(measured.sum()), 1)
        grad = np.zeros(x.size)
        np.add.at(grad, idx, 2.0 * diff / (prob.signal_spans * n))
        return float((diff**2).sum() / n), grad

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

    # -- for methods that build their own NLP around the forward problem -----------------------------
    @property
    def symbolic(self) -> SymbolicStep:
        """The forward problem's CasADi expressions (the same object for every problem of a
        process, so an NLP built on it can be cached): ``x``, ``p``, ``g``, the weighted
        features over :attr:`all_features` and the regularizer."""
        return self._solver.nlp.symbolic

    @property
    def all_features(self) -> tuple[str, ...]:
        """The forward problem's features (weights over these enter :meth:`parameters`)."""
        return self._solver.nlp.features

    @property
    def feature_columns(self) -> list[int]:
        """Where each of the problem's features sits among :attr:`all_features`."""
        return list(self._columns)

    def parameters(self, weights: np.ndarray | None = None) -> np.ndarray:
        """The value of ``symbolic.p`` for this problem's model and task, with unit ``weights``
        over the problem's features (default: all zero)."""
        return self._p(weights)

    def tracking_quadratic(self) -> tuple[np.ndarray, np.ndarray]:
        """``(ref, weight)`` over ``x`` with ``tracking_error(x) = sum(weight * (x - ref)^2)``
        (weight 0 where ``x`` holds no measured signal)."""
        prob = self._problem
        observed = prob.observed.signals(len(self._solver.nlp.actuators))
        measured = np.isfinite(observed)
        rows, cols = np.nonzero(measured)
        idx = self.signal_indices[rows, cols]
        weight, ref = np.zeros(self.n_x), np.zeros(self.n_x)
        weight[idx] = 1.0 / (prob.signal_spans[cols] ** 2 * measured.sum())
        ref[idx] = observed[rows, cols]
        return ref, weight

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
