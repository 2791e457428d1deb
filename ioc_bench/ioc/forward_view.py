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

from collections.abc import Sequence
from functools import cached_property

import numpy as np
import scipy.sparse as sp

from ioc_bench.ioc.oracle import OracleSolution, OracleStats
from ioc_bench.model.gait_model import GaitParams
from ioc_bench.task import Task
from ioc_bench.trajectory import Observation, Trajectory
from ioc_bench.trajopt.active_set import ActiveSet
from ioc_bench.trajopt.forward_problem import ForwardProblem
from ioc_bench.trajopt.step_problem import OBJECTIVE_SCALE, SymbolicStep
from ioc_bench.weights import full_weights

#: Default tolerance of :meth:`ForwardView.active_set`: at a projection IPOPT stops with a
#: weakly active constraint's slack up to ~1e-6 (measured: an inverse-KKT fit with 1e-7 missed
#: such constraints, 0.044 weight error; with 1e-5, 1.6e-6).
ACTIVE_TOL = 1e-5


class ForwardView:
    """Values and derivatives of an :class:`~ioc_bench.ioc.problem.IOCProblem`'s forward problem.

    Made by the problem (``problem.forward``); a view of one
    :class:`~ioc_bench.trajopt.forward_problem.ForwardProblem` under the model, task and
    feature set the IOC believes in. ``docs/differentiable.md`` has the optimality
    conditions, the problem's structure and sizes, and an example.

    Attributes:
        features: the IOC's features (the order of the weights in every call).
        objective_scale: ``s`` in the objective ``s * w . phi + R`` (0.25).
        n_x: length of the decision vector ``x``.
        n_g: length of the constraint vector ``g``.
    """

    def __init__(
        self,
        forward: ForwardProblem,
        features: Sequence[str],
        params: GaitParams,
        task: Task,
        observed: Observation,
        spans: np.ndarray,
        stats: OracleStats,
    ):
        self._forward = forward
        self._params, self._task, self._observed, self._spans, self._stats = params, task, observed, spans, stats
        self._d = forward.derivatives
        self._columns = [forward.features.index(f) for f in features]
        #: The IOC's features (the weights' order in every call).
        self.features: tuple[str, ...] = tuple(features)
        #: ``s`` in the objective ``s * w . phi + R``: the forward problem's objective scale.
        self.objective_scale: float = OBJECTIVE_SCALE
        #: Length of the decision vector ``x``.
        self.n_x: int = forward.n_x
        #: Length of the constraint vector ``g``.
        self.n_g: int = forward.n_g

    # -- the map between trajectories and decision vectors -------------------------------------
    def vector(self, trajectory: Trajectory) -> np.ndarray:
        """The decision vector of a full trajectory."""
        if not isinstance(trajectory, Trajectory):
            raise ValueError(
                f"trajectory must be a Trajectory (e.g. an oracle solution's), got {type(trajectory).__name__}"
            )
        return self._forward.vector(trajectory)

    def trajectory(self, x: np.ndarray) -> Trajectory:
        """The trajectory a decision vector encodes."""
        return self._forward.trajectory(self._x(x), self._params)

    @property
    def blocks(self) -> dict[str, slice]:
        """Where each named block (``dt``, ``q``, ``v``, ``force``, ``tau``, ...) sits in ``x``."""
        layout = self._forward.step.layout
        return {name: layout.slice(name) for name in layout.blocks}

    @cached_property
    def signal_indices(self) -> np.ndarray:
        """(T, n) index into ``x`` of every signal of :meth:`Observation.signals` (positions,
        velocities and torques knot by knot), so that ``x[signal_indices]`` are the signals."""
        layout = self._forward.step.layout
        t = self._forward.n_knots
        index = np.arange(layout.size)
        parts = [index[layout.slice(name)].reshape(t, -1) for name in ("q", "v", "tau")]
        return np.concatenate(parts, axis=1)

    def tracking_error(self, x: np.ndarray) -> tuple[float, np.ndarray]:
        """:meth:`IOCProblem.tracking_error` of the step ``x`` encodes, and its gradient in ``x``."""
        x = self._x(x)
        idx = self.signal_indices
        observed = self._observed.signals(len(self._forward.actuators))
        measured = np.isfinite(observed)
        diff = np.where(measured, (x[idx] - np.where(measured, observed, 0.0)) / self._spans, 0.0)
        n = max(int(measured.sum()), 1)
        grad = np.zeros(x.size)
        np.add.at(grad, idx, 2.0 * diff / (self._spans * n))
        return float((diff**2).sum() / n), grad

    @property
    def constraint_groups(self) -> dict[str, slice]:
        """Where each named constraint group (``collocation``, ``pin_position``, ...) sits in ``g``."""
        return dict(self._forward.step.constraints.groups)

    @cached_property
    def _bounds(self) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        return self._forward.bounds(self._params, self._task)

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
            return self._d.constraints(self._x(x), self._p())

    def constraint_jacobian(self, x: np.ndarray) -> sp.csc_matrix:
        """(n_g, n_x) sparse Jacobian of g."""
        with self._timed():
            return self._d.constraint_jacobian(self._x(x), self._p())

    def features_at(self, x: np.ndarray) -> np.ndarray:
        """(F,) the problem's features at x."""
        with self._timed():
            return self._d.features(self._x(x), self._p())[self._columns]

    def feature_jacobian(self, x: np.ndarray) -> sp.csc_matrix:
        """(F, n_x) sparse gradients of the problem's features (rows in feature order)."""
        with self._timed():
            return self._d.feature_jacobian(self._x(x), self._p())[self._columns]

    def feature_hessian(self, x: np.ndarray, feature: str) -> sp.csc_matrix:
        """(n_x, n_x) sparse Hessian of one of the problem's features (by name)."""
        if feature not in self.features:
            raise ValueError(f"unknown feature {feature!r}; this problem's features: {', '.join(self.features)}")
        index = self._forward.features.index(feature)
        with self._timed():
            return self._d.feature_hessian(self._x(x), self._p(), index)

    def regularizer(self, x: np.ndarray) -> float:
        """R(x): the weight-independent objective term (the knee-lock penalty)."""
        with self._timed():
            return self._d.regularizer(self._x(x), self._p())

    def regularizer_gradient(self, x: np.ndarray) -> np.ndarray:
        """(n_x,) gradient of R."""
        with self._timed():
            return self._d.regularizer_gradient(self._x(x), self._p())

    def lagrangian_hessian(self, x: np.ndarray, weights: np.ndarray, lam_g: np.ndarray) -> sp.csc_matrix:
        """(n_x, n_x) Hessian of ``s w . phi + R + lam_g . g`` for unit ``weights``."""
        lam_g = _vector(lam_g, self.n_g, "lam_g")
        with self._timed():
            return self._d.lagrangian_hessian(self._x(x), self._p(weights), lam_g)

    def active_set(self, x: np.ndarray, tol: float = ACTIVE_TOL) -> ActiveSet:
        """Which constraints and bounds hold with equality at ``x``, side by side.

        A constraint ``lbg <= g <= ubg`` is at its lower side when ``g - lbg <= tol (1 +
        |lbg|)`` (likewise upper; a variable and its bounds alike). The result's masks:
        ``equality`` (n_g: ``lbg == ubg``, always active), ``g_lower`` / ``g_upper`` (n_g:
        inequalities at their lower / upper bound), ``x_lower`` / ``x_upper`` (n_x: variables
        at a bound, fixed ones included); ``constraints`` and ``bounds`` are their unions.
        In IPOPT's sign convention an active lower side takes a multiplier <= 0 and an upper
        side one >= 0. The default ``tol`` (:data:`ACTIVE_TOL`, 1e-5) is what a projection
        needs; at an ``optimize`` solution 1e-7 is enough (the sensitivity's).
        """
        x = self._x(x)
        with self._timed():
            return self._d.active_set(x, self._p(), self._bounds, tol)

    # -- at an oracle solution ---------------------------------------------------------------------
    def duals(self, solution: OracleSolution) -> tuple[np.ndarray, np.ndarray]:
        """(lam_g, lam_x): the solution's multipliers, in IPOPT's sign convention (the
        stationarity is ``grad f + J_g^T lam_g + lam_x = 0``; a multiplier is >= 0 on an
        active upper bound and <= 0 on an active lower one).

        For an ``optimize`` solution they are the forward problem's multipliers at its
        optimum. For a ``project`` solution they belong to the projection's own objective
        (the tracking term, weights zero): an inverse-KKT method must fit its own
        multipliers at the projected step rather than reuse these.
        """
        point = _point(solution)
        return point.lam_g.copy(), point.lam_x.copy()

    def sensitivity(self, solution: OracleSolution) -> np.ndarray:
        """(n_x, F) derivative of the optimum by the weights, at an ``optimize`` solution.

        From the KKT system with the solution's active set held fixed (implicit-function
        theorem). The weights are used as given (``optimize`` normalises them to unit norm,
        so a step along ``w`` itself changes nothing: compose with that projection).
        """
        point = _point(solution)
        if solution.weights.size != len(self.features) or not np.any(solution.weights):
            raise ValueError("sensitivity needs a solution of optimize(weights), not of project()")
        p = self._p(solution.weights)
        with self._stats.timed("sensitivity"):
            active = self._d.active_set(point.x, p, self._bounds)
            dx = self._d.sensitivity(point.x, p, point.lam_g, active)
        return dx[:, self._columns]

    # -- for methods that build their own NLP around the forward problem -----------------------------
    @property
    def symbolic(self) -> SymbolicStep:
        """The forward problem's CasADi expressions (the same object for every problem of a
        process, so an NLP built on it can be cached): ``x``, ``p``, ``g``, the weighted
        features over :attr:`all_features` and the regularizer."""
        return self._forward.step.symbolic

    @property
    def all_features(self) -> tuple[str, ...]:
        """The forward problem's features (weights over these enter :meth:`parameters`)."""
        return self._forward.features

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
        observed = self._observed.signals(len(self._forward.actuators))
        measured = np.isfinite(observed)
        rows, cols = np.nonzero(measured)
        idx = self.signal_indices[rows, cols]
        weight, ref = np.zeros(self.n_x), np.zeros(self.n_x)
        weight[idx] = 1.0 / (self._spans[cols] ** 2 * measured.sum())
        ref[idx] = observed[rows, cols]
        return ref, weight

    # -- internals ----------------------------------------------------------------------------------
    def _p(self, weights: np.ndarray | None = None) -> np.ndarray:
        w = np.zeros(len(self.features)) if weights is None else _vector(weights, len(self.features), "weights")
        return self._forward.parameters(
            self._params, self._task, full_weights(w, self.features, self._forward.features)
        )

    def _x(self, x: np.ndarray) -> np.ndarray:
        return _vector(x, self.n_x, "x")

    def _timed(self):
        return self._stats.timed("derivatives")


def _vector(value: object, n: int, name: str) -> np.ndarray:
    """``value`` as a finite (n,) float vector, or a ``ValueError`` naming the argument."""
    try:
        arr = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a vector of {n} numbers, got {type(value).__name__}") from None
    if arr.shape != (n,):
        raise ValueError(f"{name} must have shape ({n},), got {arr.shape}")
    if not np.all(np.isfinite(arr)):
        raise ValueError(f"{name} has non-finite entries")
    return arr


def _point(solution: OracleSolution):
    if not isinstance(solution, OracleSolution):
        raise ValueError(
            f"expected an OracleSolution (from problem.optimize or project), got {type(solution).__name__}"
        )
    if solution.point is None:
        raise ValueError("this solution carries no solver data (it was not returned by an oracle)")
    return solution.point
