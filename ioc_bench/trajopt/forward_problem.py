"""The forward problem: one gait model's step NLP, built once per process, solved many times.

A :class:`ForwardProblem` owns everything about the step problem of one model, interval
count and feature basis: the transcribed NLP
(:class:`~ioc_bench.trajopt.step_problem.StepProblem`), its IPOPT instances (cold starts, on
lock-scaled variables; cold projections; warm primal-dual starts, as IOC inner loops re-solve
near a known optimum), the parameter vector and bounds of a solve, the map between
trajectories and decision vectors, and the derivatives (:attr:`ForwardProblem.derivatives`).
A solve takes one :class:`SolveRequest` and returns a
:class:`~ioc_bench.trajopt.solution.SolveResult`; a failed solve is a result, never an
exception.
"""

from __future__ import annotations

import time
from collections.abc import Sequence
from dataclasses import dataclass, replace
from functools import cached_property, lru_cache
from typing import Any

import casadi as ca
import numpy as np

from ioc_bench.features import check_model_names, model_features
from ioc_bench.model.gait_model import GaitModel, GaitParams
from ioc_bench.model.walker import WALKER
from ioc_bench.task import Task
from ioc_bench.trajectory import Trajectory
from ioc_bench.trajopt import ipopt
from ioc_bench.trajopt.active_set import active_sides
from ioc_bench.trajopt.derivatives import Bounds, StepDerivatives
from ioc_bench.trajopt.solution import FEASIBILITY_TOL, SolveResult, SolverReport, StartPoint
from ioc_bench.trajopt.step_problem import DEFAULT_INTERVALS, LOCK_PENALTY, LOCK_TOL, StepProblem, StepRules
from ioc_bench.trajopt.tracking import Tracking

#: Penalty raises tried, in turn, when a converged solve misses the complementarity tolerance.
REPAIR_FACTORS = (1e2, 1e4)

_TOLERANCES = {
    "tol": 1e-8,
    "constr_viol_tol": 1e-8,
    "acceptable_tol": 1e-6,
    "acceptable_constr_viol_tol": FEASIBILITY_TOL,
    "acceptable_iter": 10,
    "max_iter": 500,
}
COLD_OPTIONS = ipopt.options(ipopt.MUMPS, **_TOLERANCES, mu_init=1e-3)
WARM_OPTIONS = ipopt.options(ipopt.MUMPS, ipopt.WARM_START, **_TOLERANCES)
#: The cold solver's unit of the knee-lock torques and impulses: it solves for
#: ``lock / LOCK_SCALE``. A change of variables cannot move an optimum, but it shrinks the
#: saddle the bilinear lock penalty puts in the Hessian, so IPOPT regularises less: a cold
#: start takes about half the iterations and reaches the same optima
#: (``docs/performance.md``, "Scaling the lock torques").
LOCK_SCALE = 1e-4
#: Blocks of the decision vector that :data:`LOCK_SCALE` applies to.
LOCK_BLOCKS = ("lock", "lock_impulse")


@dataclass(frozen=True, eq=False)
class SolveRequest:
    """One forward solve: where it starts, for which model, task and weights.

    Attributes:
        start: the start point (warm when it carries multipliers).
        params: the model's parameters.
        task: the task (speed, optionally a held step length).
        weights: (F,) weights over the forward problem's :attr:`~ForwardProblem.features`.
        tracking: an optional tracking term (projections and proximal solves).
        lock_penalty: weight of the knee-lock complementarity penalty.
        rules: formulation choices (lift-off rule, cost normalisation).
    """

    start: StartPoint
    params: GaitParams
    task: Task
    weights: np.ndarray
    tracking: Tracking | None = None
    lock_penalty: float = LOCK_PENALTY
    rules: StepRules = StepRules()


class ForwardProblem:
    """The step NLP of ``model`` with ``n_intervals`` Hermite-Simpson intervals, and its solvers.

    ``features`` is the basis the objective weighs, in weight order: by default the model's
    :func:`~ioc_bench.features.model_features`; any of its
    :func:`~ioc_bench.features.available_features` may be named (e.g. adding ``work`` and
    ``collision``). :attr:`features` says which.
    """

    def __init__(
        self,
        model: GaitModel = WALKER,
        n_intervals: int = DEFAULT_INTERVALS,
        lock_scale: float = LOCK_SCALE,
        *,
        features: Sequence[str] | None = None,
    ):
        self.model = model
        #: :func:`basis_key` of the basis: None for the model's default, else its names.
        self.basis = basis_key(model, features)
        self.step = StepProblem(model, n_intervals, self.basis)
        self._scale = np.ones(self.step.layout.size)
        for name in LOCK_BLOCKS:
            self._scale[self.step.layout.slice(name)] = lock_scale
        self._cold_plain = ca.nlpsol("gait_cold_plain", "ipopt", self.step.casadi_nlp, COLD_OPTIONS)
        scaled = bool(np.any(self._scale != 1.0))  # a model without lock variables has nothing to scale
        nlp = _scaled(self.step.casadi_nlp, self._scale) if scaled else None
        self._cold = ca.nlpsol("gait_cold", "ipopt", nlp, COLD_OPTIONS) if scaled else self._cold_plain
        self._warm = ca.nlpsol("gait_warm", "ipopt", self.step.casadi_nlp, WARM_OPTIONS)

    # -- sizes and names -----------------------------------------------------------------
    @property
    def n_intervals(self) -> int:
        return self.step.n_intervals

    @property
    def n_knots(self) -> int:
        return self.step.n_knots

    @property
    def features(self) -> tuple[str, ...]:
        """The features the objective weighs, in weight order."""
        return self.step.features

    @property
    def actuators(self) -> tuple[str, ...]:
        return self.step.actuators

    @property
    def n_x(self) -> int:
        return self.step.layout.size

    @property
    def n_g(self) -> int:
        return len(self.step.constraints.lb)

    @cached_property
    def derivatives(self) -> StepDerivatives:
        """Values and derivatives of the NLP at any point, and the sensitivity of optima."""
        return StepDerivatives(self.step, self.oracle)

    def oracle(self, name: str) -> ca.Function:
        """One of the built IPOPT instance's own derivative functions (e.g. ``nlp_jac_g``), in
        the NLP's own variables."""
        return self._warm.get_function(name)

    # -- what a solve is given -----------------------------------------------------------
    def parameters(
        self,
        params: GaitParams,
        task: Task,
        weights: np.ndarray | None = None,
        tracking: Tracking | None = None,
        lock_penalty: float = LOCK_PENALTY,
        rules: StepRules = StepRules(),
    ) -> np.ndarray:
        """The NLP's parameter vector (``weights`` over :attr:`features`, default all zero)."""
        w = np.zeros(len(self.features)) if weights is None else weights
        ref, track, smooth = (
            (None, None, 0.0) if tracking is None else (tracking.ref, tracking.weight, tracking.smoothing)
        )
        return self.step.parameter_vector(
            params, task.speed, w, ref=ref, track=track, smoothing=smooth, lock_penalty=lock_penalty, rules=rules
        )

    def bounds(self, params: GaitParams, task: Task, rules: StepRules = StepRules()) -> Bounds:
        """(lbx, ubx, lbg, ubg) for a model, a task and the formulation's rules."""
        return (*self.step.variable_bounds(params, rules), *self.step.constraint_bounds(task.step_length, rules))

    # -- solving -------------------------------------------------------------------------
    def solve(self, request: SolveRequest) -> SolveResult:
        """Solve from ``request.start``.

        If IPOPT converges to a feasible point whose knee-lock complementarity misses
        ``LOCK_TOL`` (the penalty was too weak against the rest of the objective; measured
        in 8 of 1070 IOC forward solves), the solve is repeated, warm-started from that
        point, with the penalty raised by :data:`REPAIR_FACTORS`; the report then says
        ``repaired`` and counts every iteration.
        """
        result = self._solve_once(request)
        first = result.report
        for factor in REPAIR_FACTORS:
            r = result.report
            if r.success or not (r.converged and r.max_violation <= FEASIBILITY_TOL):
                break
            again = replace(request, start=result.point, lock_penalty=request.lock_penalty * factor)
            result = self._solve_once(again)
            report = replace(
                result.report,
                iterations=first.iterations + result.report.iterations,
                wall_time=first.wall_time + result.report.wall_time,
                warm=request.start.warm,
                repaired=True,
            )
            result = replace(result, report=report)
            first = result.report
        return result

    def _solver_for(self, request: SolveRequest) -> tuple[ca.Function, np.ndarray | float]:
        """The IPOPT instance for a request and the unit of its variables.

        Cold solves of the step use the lock-scaled instance. Cold projections (a tracking
        term) keep the NLP's own variables: the reference of an observation, which every
        algorithm starts from, is then the one it always was (measured: ``single-level``'s
        last stage fails in a multi-trial case from the reference the scaled instance finds,
        an equally valid projection within IPOPT's tolerance).
        """
        if request.start.warm:
            return self._warm, 1.0
        if request.tracking is not None:
            return self._cold_plain, 1.0
        return self._cold, self._scale

    def _solve_once(self, request: SolveRequest) -> SolveResult:
        p = self.parameters(
            request.params, request.task, request.weights, request.tracking, request.lock_penalty, request.rules
        )
        lbx, ubx, lbg, ubg = bounds = self.bounds(request.params, request.task, request.rules)
        start = request.start
        x0 = np.clip(start.x, lbx, ubx)
        solver, d = self._solver_for(request)
        args = {"x0": x0 / d, "p": p, "lbx": lbx / d, "ubx": ubx / d, "lbg": lbg, "ubg": ubg}
        if start.warm:
            args |= {"lam_x0": start.lam_x, "lam_g0": start.lam_g}
        t0 = time.perf_counter()
        try:
            sol = solver(**args)
            stats = solver.stats()
            status = str(stats.get("return_status", "unknown"))
            iterations = int(stats.get("iter_count", -1))
        except RuntimeError as exc:  # an evaluation error inside IPOPT
            sol = {"x": x0 / d, "lam_x": np.zeros_like(x0), "lam_g": np.zeros(len(lbg))}
            status, iterations = f"error: {exc}", -1
        wall = time.perf_counter() - t0
        x = np.asarray(sol["x"], dtype=float).ravel() * d
        return SolveResult(
            trajectory=self._trajectory(x, p),
            report=self._report(x, p, bounds, status, iterations, wall, start.warm),
            x=x,
            lam_x=np.asarray(sol["lam_x"], dtype=float).ravel() / d,
            lam_g=np.asarray(sol["lam_g"], dtype=float).ravel(),
        )

    def _report(self, x, p, bounds: Bounds, status, iterations, wall, warm) -> SolverReport:
        violation = self.max_violation(x, p, bounds)
        products = float(np.max(np.asarray(self.step.lock_fn(x, p), dtype=float), initial=0.0))
        return SolverReport(
            status=status,
            success=bool(ipopt.converged(status) and violation <= FEASIBILITY_TOL and products <= LOCK_TOL),
            max_violation=violation,
            complementarity=products,
            iterations=iterations,
            wall_time=wall,
            objective=float(self.step.effort_fn(x, p)),
            warm=warm,
        )

    # -- checking a point ----------------------------------------------------------------
    def max_violation(self, x: np.ndarray, p: np.ndarray, bounds: Bounds) -> float:
        """Largest violation of any constraint or variable bound at ``x``."""
        lbx, ubx, lbg, ubg = bounds
        g = np.asarray(self.step.g_fn(x, p), dtype=float).ravel()
        worst = float(np.max(np.maximum(np.maximum(lbg - g, g - ubg), 0.0), initial=0.0))
        bound = float(np.max(np.maximum(np.maximum(lbx - x, x - ubx), 0.0), initial=0.0))
        value = max(worst, bound)
        return value if np.isfinite(value) else float("inf")

    def violation_of(self, traj: Trajectory, params: GaitParams, task: Task, rules: StepRules = StepRules()) -> float:
        """Largest constraint or bound violation of a recorded step under a model and task."""
        p = self.parameters(params, task, rules=rules)
        return self.max_violation(self.vector(traj), p, self.bounds(params, task, rules))

    def active_bounds(
        self, x: np.ndarray, params: GaitParams, task: Task, rules: StepRules = StepRules(), tol: float = 1e-6
    ) -> dict[str, int]:
        """Inequality constraints and variable bounds that hold with equality at ``x``.

        Returns how many entries are active, keyed ``<group>`` / ``<group>:upper`` for
        constraint groups and ``bound:<block>:lower|upper|zero`` for variable blocks (``zero``:
        a bound at 0, such as the ground's ``f_z >= 0``); see
        :func:`~ioc_bench.trajopt.step_problem.classify_active`.
        """
        lbx, ubx, lbg, ubg = self.bounds(params, task, rules)
        g = np.asarray(self.step.g_fn(x, self.parameters(params, task, rules=rules)), dtype=float).ravel()
        out: dict[str, int] = {}
        for name, sl in self.step.constraints.groups.items():
            lower, upper = _inequality_sides(g[sl], lbg[sl], ubg[sl], tol)
            out[name] = int(lower.sum())
            out[f"{name}:upper"] = int(upper.sum())
        for name in self.step.layout.blocks:
            sl = self.step.layout.slice(name)
            lower, upper = _inequality_sides(x[sl], lbx[sl], ubx[sl], tol)
            zero = (lower & (lbx[sl] == 0)) | (upper & (ubx[sl] == 0))
            out[f"bound:{name}:zero"] = int(zero.sum())
            out[f"bound:{name}:lower"] = int((lower & ~zero).sum())
            out[f"bound:{name}:upper"] = int((upper & ~zero).sum())
        return {k: v for k, v in out.items() if v}

    # -- trajectories and decision vectors -----------------------------------------------
    def trajectory(self, x: np.ndarray, params: GaitParams) -> Trajectory:
        """The :class:`Trajectory` decision vector ``x`` encodes under a model's parameters."""
        return self._trajectory(np.asarray(x, dtype=float), self.parameters(params, Task()))

    def _trajectory(self, x: np.ndarray, p: np.ndarray) -> Trajectory:
        b = self.step.layout.unpack(x)
        acc = np.asarray(self.step.acc_fn(x, p), dtype=float).reshape(b["q"].shape)
        return Trajectory(
            dt=float(np.mean(b["dt"])),
            q=b["q"],
            v=b["v"],
            acc=acc,
            tau=b["tau"],
            lock=b["lock"],
            pin_forces=b["force"],
            impulses=b["impulse"],
            trail_impulse=b["trail_impulse"],
            lock_impulses=b["lock_impulse"],
        )

    def vector(self, traj: Trajectory) -> np.ndarray:
        """Inverse of :meth:`trajectory`: the decision vector of a recorded step."""
        if traj.n_knots != self.n_knots:
            raise ValueError(
                f"trajectory has {traj.n_knots} knots but the solver uses {self.n_knots} ({self.n_intervals} intervals)"
            )
        return self.step.layout.pack(
            {
                "dt": traj.dt,
                "q": traj.q,
                "v": traj.v,
                "force": traj.pin_forces,
                "tau": traj.tau,
                "lock": traj.lock,
                "impulse": traj.impulses,
                "trail_impulse": traj.trail_impulse,
                "lock_impulse": traj.lock_impulses,
            }
        )

    def guess_vector(self, step: Any, params: GaitParams) -> np.ndarray:
        """A decision vector from what is observed of a step (knot spacing, positions,
        velocities, torques if measured): the body's weight on the stance foot, every other
        force, lock torque and impulse zero. A start point, not a solution."""
        force = np.zeros(self.step.layout.blocks["force"][1])
        force[:, self.step.contact, 1] = params.total_mass * params.gravity
        blocks = {"dt": step.dt, "q": step.q, "v": step.v, "force": force}
        if step.tau is not None:
            blocks["tau"] = step.tau
        return self.step.layout.pack(blocks)


def _scaled(nlp: dict[str, ca.SX], d: np.ndarray) -> dict[str, ca.SX]:
    """``nlp`` in the variables ``y = x / d`` (the same problem: its optima are ``x = d * y``)."""
    y = ca.SX.sym("y", nlp["x"].numel())
    x = y * ca.DM(d)
    f, g = ca.substitute([nlp["f"], nlp["g"]], [nlp["x"]], [x])
    return {"x": y, "p": nlp["p"], "f": f, "g": g}


def _inequality_sides(values: np.ndarray, lower: np.ndarray, upper: np.ndarray, tol: float) -> tuple[np.ndarray, ...]:
    """:func:`active_sides` of the inequality entries only (lower < upper)."""
    at_lower, at_upper = active_sides(values, lower, upper, tol)
    inequality = lower < upper
    return inequality & at_lower, inequality & at_upper


def basis_key(model: GaitModel, features: Sequence[str] | None) -> tuple[str, ...] | None:
    """The key of a feature basis of ``model``: None for its default basis
    (:func:`~ioc_bench.features.model_features`, whether given as None or by its names),
    else the names as a tuple, so that two bases never share a built problem.

    Raises:
        ValueError: a string instead of a sequence of names, no name, an unknown feature, or
            a feature the model lacks (the message lists the model's features).
    """
    if features is None:
        return None
    if isinstance(features, (str, bytes)):
        raise ValueError(f"features must be a sequence of feature names, got the string {features!r}")
    if not isinstance(features, Sequence):
        raise ValueError(f"features must be a sequence of feature names, got {type(features).__name__}")
    if len(features) == 0:
        raise ValueError(f"features must name at least one feature of model {model.name!r}")
    names = check_model_names(model, tuple(features))
    return None if names == model_features(model) else names


def get_forward_problem(
    model: GaitModel = WALKER, n_intervals: int = DEFAULT_INTERVALS, features: Sequence[str] | None = None
) -> ForwardProblem:
    """This process's forward problem for a model, ``n_intervals`` and a feature basis
    (default: the model's :func:`~ioc_bench.features.model_features`), built on first use (a
    few seconds). One instance per (model, intervals, :func:`basis_key`): the default basis
    named in full is the default's instance, any other basis has its own."""
    return _forward_problem(model, n_intervals, basis_key(model, features))


@lru_cache(maxsize=4)
def _forward_problem(model: GaitModel, n_intervals: int, key: tuple[str, ...] | None) -> ForwardProblem:
    return ForwardProblem(model, n_intervals, features=key)
