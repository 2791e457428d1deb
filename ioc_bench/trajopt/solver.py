"""IPOPT on the gait NLP: built once per process, solved many times.

One :class:`GaitSolver` holds two compiled IPOPT instances over the same NLP, one for
cold starts and one tuned for warm primal-dual starts (IOC inner loops re-solve near a
known optimum). Every solve returns a :class:`SolveResult` whose :class:`SolverReport`
says whether it is valid: IPOPT converged, constraints and bounds hold to
:data:`FEASIBILITY_TOL` and the knee-lock complementarity to ``LOCK_TOL``. A failed solve
is a result, never an exception.
"""

from __future__ import annotations

import time
from dataclasses import asdict, dataclass, replace
from functools import lru_cache
from typing import Any

import casadi as ca
import numpy as np

from ioc_bench.model.gait_model import GaitModel, GaitParams
from ioc_bench.model.walker import WALKER
from ioc_bench.task import Task
from ioc_bench.trajectory import Trajectory
from ioc_bench.trajopt.step_problem import DEFAULT_INTERVALS, LOCK_PENALTY, LOCK_TOL, StepProblem, StepRules

#: A solution is feasible when IPOPT converged and no constraint or bound is violated by more.
FEASIBILITY_TOL = 1e-6
#: IPOPT statuses that count as converged.
CONVERGED = ("Solve_Succeeded", "Solved_To_Acceptable_Level")
#: Penalty raises tried, in turn, when a converged solve misses the complementarity tolerance.
REPAIR_FACTORS = (1e2, 1e4)

_COMMON = {
    "ipopt.print_level": 0,
    "ipopt.sb": "yes",
    "print_time": False,
    "ipopt.tol": 1e-8,
    "ipopt.constr_viol_tol": 1e-8,
    "ipopt.acceptable_tol": 1e-6,
    "ipopt.acceptable_constr_viol_tol": FEASIBILITY_TOL,
    "ipopt.acceptable_iter": 10,
    # The KKT systems are banded and well scaled; MUMPS' own scaling and tight
    # pivoting only slow each factorization down (2-3x measured).
    "ipopt.mumps_scaling": 0,
    "ipopt.mumps_permuting_scaling": 0,
    "ipopt.mumps_pivtol": 1e-8,
    # No bound relaxation: relaxed by 1e-8, idle lock torques sat at -1e-8 where the knee
    # was flexed, the lock penalty rewarded it (2e-5 of objective at a demonstration) and a
    # projection of a demonstration onto itself stopped 1e-8 (tracking error) away.
    "ipopt.bound_relax_factor": 0.0,
}
COLD_OPTIONS = _COMMON | {"ipopt.max_iter": 500, "ipopt.mu_init": 1e-3}
WARM_OPTIONS = _COMMON | {
    "ipopt.max_iter": 500,
    "ipopt.warm_start_init_point": "yes",
    "ipopt.mu_init": 1e-6,
    "ipopt.warm_start_bound_push": 1e-9,
    "ipopt.warm_start_bound_frac": 1e-9,
    "ipopt.warm_start_slack_bound_push": 1e-9,
    "ipopt.warm_start_slack_bound_frac": 1e-9,
    "ipopt.warm_start_mult_bound_push": 1e-9,
}


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
        repaired: whether a complementarity repair re-solve was needed (see ``solve``).
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
        return self.status in CONVERGED

    def to_dict(self) -> dict[str, Any]:
        return asdict(self)


@dataclass(frozen=True, eq=False)
class SolveResult:
    """A solve's trajectory and report, plus the primal-dual point for warm starts."""

    trajectory: Trajectory
    report: SolverReport
    x: np.ndarray
    lam_x: np.ndarray
    lam_g: np.ndarray


@dataclass(frozen=True, eq=False)
class StartPoint:
    """Where a solve starts: a primal point and, for a warm start, its multipliers."""

    x: np.ndarray
    lam_x: np.ndarray | None = None
    lam_g: np.ndarray | None = None

    @property
    def warm(self) -> bool:
        return self.lam_x is not None and self.lam_g is not None


class GaitSolver:
    """Compiled IPOPT solvers for a gait model's step problem with ``n_intervals`` intervals."""

    def __init__(self, n_intervals: int = DEFAULT_INTERVALS, model: GaitModel = WALKER):
        self.model = model
        self.nlp = StepProblem(model, n_intervals)
        self._cold = ca.nlpsol("gait_cold", "ipopt", self.nlp.nlp, COLD_OPTIONS)
        self._warm = ca.nlpsol("gait_warm", "ipopt", self.nlp.nlp, WARM_OPTIONS)

    @property
    def n_intervals(self) -> int:
        return self.nlp.n_intervals

    def oracle(self, name: str) -> ca.Function:
        """One of the built IPOPT instance's own derivative functions (e.g. ``nlp_jac_g``)."""
        return self._cold.get_function(name)

    def guess_vector(self, step: Any, params: GaitParams) -> np.ndarray:
        """A decision vector from what is observed of a step (knot spacing, positions,
        velocities, torques if measured): the body's weight on the stance foot, every other
        force, lock torque and impulse zero. A start point, not a solution."""
        force = np.zeros(self.nlp.layout.blocks["force"][1])
        force[:, self.nlp.contact, 1] = params.total_mass * params.gravity
        blocks = {"dt": step.dt, "q": step.q, "v": step.v, "force": force}
        if step.tau is not None:
            blocks["tau"] = step.tau
        return self.nlp.layout.pack(blocks)

    def solve(
        self,
        start: StartPoint,
        params: GaitParams,
        task: Task,
        weights: np.ndarray,
        ref: np.ndarray | None = None,
        track: np.ndarray | None = None,
        lock_penalty: float = LOCK_PENALTY,
        rules: StepRules = StepRules(),
    ) -> SolveResult:
        """Solve from ``start`` for the model ``params`` and ``task``.

        If IPOPT converges to a feasible point whose knee-lock complementarity misses
        ``LOCK_TOL`` (the penalty was too weak against the rest of the objective; measured
        in 8 of 1070 IOC forward solves), the solve is repeated, warm-started from that
        point, with the penalty raised by :data:`REPAIR_FACTORS`; the report then says
        ``repaired`` and counts every iteration.

        Args:
            weights: (F,) weights over the problem's features (``self.nlp.features``).
            ref, track: optional (T, n_track) tracking reference and its weights.
            lock_penalty: weight of the knee-lock complementarity penalty.
            rules: formulation choices (lift-off rule, cost normalisation).
        """
        result = self._solve_once(start, params, task, weights, ref, track, lock_penalty, rules)
        first = result.report
        for factor in REPAIR_FACTORS:
            r = result.report
            if r.success or not (r.converged and r.max_violation <= FEASIBILITY_TOL):
                break
            warm = StartPoint(result.x, result.lam_x, result.lam_g)
            result = self._solve_once(warm, params, task, weights, ref, track, lock_penalty * factor, rules)
            result = replace(
                result,
                report=replace(
                    result.report,
                    iterations=first.iterations + result.report.iterations,
                    wall_time=first.wall_time + result.report.wall_time,
                    warm=start.warm,
                    repaired=True,
                ),
            )
            first = result.report
        return result

    def _solve_once(self, start, params, task, weights, ref, track, lock_penalty, rules) -> SolveResult:
        p = self.nlp.parameter_vector(
            params, task.speed, weights, ref=ref, track=track, lock_penalty=lock_penalty, rules=rules
        )
        lbx, ubx = self.nlp.variable_bounds(params, rules)
        lbg, ubg = self.nlp.constraint_bounds(task.step_length, rules)
        x0 = np.clip(start.x, lbx, ubx)
        args = {"x0": x0, "p": p, "lbx": lbx, "ubx": ubx, "lbg": lbg, "ubg": ubg}
        solver = self._warm if start.warm else self._cold
        if start.warm:
            args |= {"lam_x0": start.lam_x, "lam_g0": start.lam_g}
        t0 = time.perf_counter()
        try:
            sol = solver(**args)
            stats = solver.stats()
            status = str(stats.get("return_status", "unknown"))
            iterations = int(stats.get("iter_count", -1))
        except RuntimeError as exc:  # an evaluation error inside IPOPT
            sol, status, iterations = (
                {"x": x0, "lam_x": np.zeros_like(x0), "lam_g": np.zeros(len(args["lbg"]))},
                f"error: {exc}",
                -1,
            )
        wall = time.perf_counter() - t0
        x = np.asarray(sol["x"], dtype=float).ravel()
        report = self._report(x, p, (lbx, ubx, lbg, ubg), status, iterations, wall, start.warm)
        return SolveResult(
            trajectory=self.trajectory(x, p),
            report=report,
            x=x,
            lam_x=np.asarray(sol["lam_x"], dtype=float).ravel(),
            lam_g=np.asarray(sol["lam_g"], dtype=float).ravel(),
        )

    def _report(self, x, p, bounds, status, iterations, wall, warm) -> SolverReport:
        violation = self.max_violation(x, p, *bounds)
        converged = status in CONVERGED
        products = float(np.max(np.asarray(self.nlp.lock_fn(x, p), dtype=float), initial=0.0))
        return SolverReport(
            status=status,
            success=bool(converged and violation <= FEASIBILITY_TOL and products <= LOCK_TOL),
            max_violation=violation,
            complementarity=products,
            iterations=iterations,
            wall_time=wall,
            objective=float(self.nlp.effort_fn(x, p)),
            warm=warm,
        )

    def max_violation(
        self, x: np.ndarray, p: np.ndarray, lbx: np.ndarray, ubx: np.ndarray, lbg: np.ndarray, ubg: np.ndarray
    ) -> float:
        """Largest violation of any constraint or variable bound at ``x``."""
        g = np.asarray(self.nlp.g_fn(x, p), dtype=float).ravel()
        worst = float(np.max(np.maximum(np.maximum(lbg - g, g - ubg), 0.0), initial=0.0))
        bound = float(np.max(np.maximum(np.maximum(lbx - x, x - ubx), 0.0), initial=0.0))
        value = max(worst, bound)
        return value if np.isfinite(value) else float("inf")

    def active_bounds(
        self, x: np.ndarray, params: GaitParams, task: Task, rules: StepRules = StepRules(), tol: float = 1e-6
    ) -> dict[str, int]:
        """Inequality constraints and variable bounds that hold with equality at ``x``.

        Returns how many entries are active, keyed ``<group>`` / ``<group>:upper`` for
        constraint groups and ``bound:<block>:lower|upper|zero`` for variable blocks (``zero``:
        a bound at 0, such as the ground's ``f_z >= 0``); see
        :func:`~ioc_bench.trajopt.step_problem.classify_active`.
        """
        p = self.nlp.parameter_vector(params, task.speed, np.zeros(len(self.nlp.features)), rules=rules)
        lbx, ubx = self.nlp.variable_bounds(params, rules)
        lbg, ubg = self.nlp.constraint_bounds(task.step_length, rules)
        g = np.asarray(self.nlp.g_fn(x, p), dtype=float).ravel()
        out: dict[str, int] = {}
        for name, sl in self.nlp.constraints.groups.items():
            lower, upper = _active_sides(g[sl], lbg[sl], ubg[sl], tol)
            out[name] = int(lower.sum())
            out[f"{name}:upper"] = int(upper.sum())
        for name in self.nlp.layout.blocks:
            sl = self.nlp.layout.slice(name)
            lower, upper = _active_sides(x[sl], lbx[sl], ubx[sl], tol)
            zero = (lower & (lbx[sl] == 0)) | (upper & (ubx[sl] == 0))
            out[f"bound:{name}:zero"] = int(zero.sum())
            out[f"bound:{name}:lower"] = int((lower & ~zero).sum())
            out[f"bound:{name}:upper"] = int((upper & ~zero).sum())
        return {k: v for k, v in out.items() if v}

    def violation_of(self, traj: Trajectory, params: GaitParams, task: Task, rules: StepRules = StepRules()) -> float:
        """Largest constraint or bound violation of a recorded step under a model and task."""
        x = self.decision_vector(traj)
        p = self.nlp.parameter_vector(params, task.speed, np.zeros(len(self.nlp.features)), rules=rules)
        lbx, ubx = self.nlp.variable_bounds(params, rules)
        return self.max_violation(x, p, lbx, ubx, *self.nlp.constraint_bounds(task.step_length, rules))

    def trajectory(self, x: np.ndarray, p: np.ndarray) -> Trajectory:
        """The :class:`Trajectory` encoded by decision vector ``x``."""
        b = self.nlp.layout.unpack(x)
        acc = np.asarray(self.nlp.acc_fn(x, p), dtype=float).reshape(b["q"].shape)
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

    def decision_vector(self, traj: Trajectory) -> np.ndarray:
        """Inverse of :meth:`trajectory`: the decision vector of a recorded step."""
        if traj.n_knots != self.nlp.n_knots:
            raise ValueError(
                f"trajectory has {traj.n_knots} knots but the solver uses {self.nlp.n_knots} "
                f"({self.nlp.n_intervals} intervals)"
            )
        return self.nlp.layout.pack(
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


def _active_sides(values: np.ndarray, lower: np.ndarray, upper: np.ndarray, tol: float) -> tuple[np.ndarray, ...]:
    """Masks of the inequality entries (lower < upper) at their lower and at their upper bound."""
    inequality = lower < upper
    with np.errstate(invalid="ignore"):
        at_lower = np.isfinite(lower) & (values - lower <= tol * (1 + np.abs(lower)))
        at_upper = np.isfinite(upper) & (upper - values <= tol * (1 + np.abs(upper))) & ~at_lower
    return inequality & at_lower, inequality & at_upper


@lru_cache(maxsize=4)
def get_solver(n_intervals: int = DEFAULT_INTERVALS, model: GaitModel = WALKER) -> GaitSolver:
    """This process's solver for a model and ``n_intervals`` (built on first use, a few seconds)."""
    return GaitSolver(n_intervals, model)
