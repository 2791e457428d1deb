"""Single-level IOC: one NLP over the weights and, per trial, a step and its multipliers.

After the single-level formulation of Becanovic, Jovanovic & Bonnet (Humanoids 2024): instead
of nesting forward solves, fit the observation with a step that is itself optimal, by
imposing the forward problem's KKT conditions (``docs/differentiable.md``)::

    min_{w, x, nu, lam}  k D(x, observation) + eps (|nu - nu0|^2 + |lam - lam0|^2)
    s.t.  lbg <= g(x) <= ubg,   lbx <= x <= ubx                  (the step is feasible)
          s J_phi(x)^T w + grad R(x) + J_g(x)^T nu + lam = 0     (and stationary for w)
          |w| = 1,  w >= 0                                       (R does not scale with w)
          nu_i (b_i - g_i) <= t,   lam_j (b_j - x_j) <= t        (relaxed complementarity)

The inequalities (ground forces, friction cones, knee lock and range, torque bounds) are
handled as a mathematical program with complementarity constraints:

- **multipliers only near activity**: equality constraints get free multipliers; an
  inequality or bound within :attr:`SingleLevelConfig.near_tol` of its bound at the start (or
  at the feasible reference) gets a sign-constrained multiplier and a complementarity row
  (``b`` its nearer bound); every other one gets none (it is held inactive by having none);
- **Scholtes' relaxation** (the default): the products of multipliers and slacks are kept
  below ``t``, and ``t`` is driven to the forward solves' feasibility tolerance over a few
  warm solves (:attr:`SingleLevelConfig.relaxation`), each started at the last one's
  primal-dual point, so the active set can change while ``t`` is large and is exact at the
  end. ``complementarity="penalty"`` is the alternative measured in ``docs/ioc.md``: the
  products' sum, times a rising weight, in the objective (an exact penalty);
- **started where model and data agree**: at a KKT point of the forward problem, the optimum
  (with its duals) of the better, by tracking error, of the uniform and the inverse-KKT
  weights, each solved warm from the feasible reference, and on an observation without
  torques also ``bilevel``'s fit from those starts (:attr:`SingleLevelConfig.bilevel_start`).
  The projection of a perturbed observation satisfies the optimality conditions for no
  weights; a forward optimum does, for its own.

The answer is then checked as a forward optimum: one forward solve for the fitted weights,
warm from the NLP's primal-dual point. Its step gives the tracking error, the 95 % region
(the Gauss-Newton covariance of the tracking residual, :func:`~ioc_bench.ioc.misfit.
gauss_newton_region`) and the misfit test (:func:`~ioc_bench.ioc.misfit.residual_test`).

Several trials (a :class:`~ioc_bench.ioc.problem.MultiTrialProblem`) share ``w`` and have a
step and multipliers each. The NLP is built once per process and problem shape (number of
trials and knots; about 10 s a trial: it needs third derivatives), by ``prepare()`` for the
benchmark's one-trial shape.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache

import casadi as ca
import numpy as np

from ioc_bench.ioc.algorithm import IOCAlgorithm, IOCResult, IterationRecord
from ioc_bench.ioc.bilevel import refine
from ioc_bench.ioc.inverse_kkt import InverseKKTConfig, fit_kkt_trials
from ioc_bench.ioc.misfit import gauss_newton_region, residual_test, tracking_residuals
from ioc_bench.ioc.nearest_optimum import nearest_optimum
from ioc_bench.ioc.oracle import OracleSolution
from ioc_bench.ioc.problem import IOCProblem
from ioc_bench.ioc.registry import register_algorithm
from ioc_bench.ioc.starts import further_starts, unit
from ioc_bench.model.walker import WALKER
from ioc_bench.trajopt import ipopt
from ioc_bench.trajopt.forward_problem import get_forward_problem
from ioc_bench.trajopt.solution import StartPoint
from ioc_bench.trajopt.step_problem import DEFAULT_INTERVALS, StepRules, SymbolicStep
from ioc_bench.validation import check_non_negative

#: The start is a KKT point: keep IPOPT there (no barrier push away from the bounds).
_OPTIONS = ipopt.options(ipopt.MUMPS, ipopt.WARM_START, tol=1e-6, constr_viol_tol=1e-6)
#: Scale of the tracking error in the objective (5 % noise gives D ~ 2.5e-3).
TRACKING_SCALE = 1e4
#: Weight of the proximal term on the multipliers (picks one where they are not unique).
MULTIPLIER_PROXIMAL = 1e-6
#: Lowest unnormalised weight of an inverse-KKT start (a zero weight starts on a face).
START_FLOOR = 1e-3
#: A start whose tracking error is at most this is the answer: the NLP's objective there
#: (:data:`TRACKING_SCALE` times it) is below IPOPT's tolerance (1e-6) and the start is an
#: exact KKT point, so the NLP is solved already. Measured on an exact observation
#: (``docs/ioc.md``): running the stages from such a start moved its tracking error from
#: 5e-11 to 2e-9.
EXACT_START = 1e-6 / TRACKING_SCALE


@dataclass(frozen=True)
class SingleLevelConfig:
    """Settings of the single-level fit.

    Attributes:
        complementarity: ``"scholtes"`` (products of multipliers and slacks at most ``t``)
            or ``"penalty"`` (their sum in the objective, weighted by ``1 / t``).
        relaxation: the ``t`` of each solve, in order; each starts at the forward optimum
            of the last one's weights (an exact KKT point), so the last, at the forward
            solves' feasibility tolerance, begins feasible. Measured: tightening ``t`` from
            1e-4 to 1e-5 warm from the relaxed solution instead stalled at the iteration
            limit (the start violates the new products by 1e-3 and IPOPT's steps shrink to
            1e-3), and holding its identified active set exactly was infeasible.
        near_tol: an inequality or bound within this (times ``1 + |bound|``) of its bound at
            the start or at the feasible reference gets a multiplier.
        init: where the weights start: ``"best"`` (the lower tracking error of the uniform and
            inverse-KKT weights' optima), ``"uniform"`` or ``"inverse-kkt"``.
        proximal: on an observation without torques, if > 0, the start's forward solves
            are also made through a proximal step of this weight towards the reference, and
            the optimum nearer the observation kept (:func:`~ioc_bench.ioc.nearest_optimum.
            nearest_optimum`), so the start is the KKT point nearer the observed step. 0:
            straight from the reference only.
        restarts: with ``init="best"``, the stages run from this many more of the ranked
            starts while the answer's residual is more than noise (the misfit test); the
            answer with the lowest tracking error is kept.
        bilevel_start: with ``init="best"``, on an observation without torques, the ranked
            starts' weights are also fitted as ``bilevel`` fits them (Gauss-Newton from the
            best, from the next while the fit is more than noise, every forward solve from
            the projection: :func:`~ioc_bench.ioc.bilevel.refine`), and that fit's optimum,
            a KKT point fitted to the observation, is ranked with the starts. From the
            uniform or inverse-KKT optimum alone the stages ended 0.10-0.21 from the truth
            on kinematics-only cases (``docs/ioc.md``); with torques the projection holds
            the step in the observed basin.
        max_iterations: IPOPT iterations at most per solve.
    """

    complementarity: str = "scholtes"
    relaxation: tuple[float, ...] = (1e-3, 1e-6)
    near_tol: float = 1e-3
    init: str = "best"
    proximal: float = 0.0
    restarts: int = 1
    bilevel_start: bool = True
    max_iterations: int = 300

    def __post_init__(self) -> None:
        if self.complementarity not in ("scholtes", "penalty"):
            raise ValueError(f"complementarity must be 'scholtes' or 'penalty', got {self.complementarity!r}")
        if self.init not in ("best", "uniform", "inverse-kkt"):
            raise ValueError(f"init must be 'best', 'uniform' or 'inverse-kkt', got {self.init!r}")
        if not self.relaxation or any(not t > 0 for t in self.relaxation):
            raise ValueError("relaxation must be one or more numbers > 0")
        if not self.near_tol > 0 or self.max_iterations < 1:
            raise ValueError("near_tol must be > 0 and max_iterations >= 1")
        if isinstance(self.restarts, bool) or not isinstance(self.restarts, int) or self.restarts < 0:
            raise ValueError(f"restarts must be an integer >= 0, got {self.restarts!r}")
        if not isinstance(self.bilevel_start, bool):
            raise ValueError(f"bilevel_start must be true or false, got {self.bilevel_start!r}")
        check_non_negative(self.proximal, "proximal")


class _NLP:
    """The single-level NLP of ``n_trials`` trials of one forward problem (structure fixed;
    the active-set candidates, the observation and the relaxation are per-case bounds and
    parameters). Variables: ``w``, then per trial ``x, nu, lam``; constraints: per trial
    ``g, stationarity, comp_g (inequality rows), comp_x``, then ``|w|^2 = 1``."""

    def __init__(self, step: SymbolicStep, inequality: tuple[int, ...], n_trials: int, max_iterations: int):
        self.n_x, self.n_g, self.n_w = step.x.numel(), step.g.numel(), len(step.features)
        self.inequality, self.n_trials = np.array(inequality, dtype=int), n_trials
        kkt = _trial_function(step, self.inequality)
        w, t, rho = ca.SX.sym("w", self.n_w), ca.SX.sym("t"), ca.SX.sym("rho")
        xs, ps, cons, f = [w], [t, rho], [], 0
        for k in range(n_trials):
            x, nu, lam = ca.SX.sym(f"x{k}", self.n_x), ca.SX.sym(f"nu{k}", self.n_g), ca.SX.sym(f"lam{k}", self.n_x)
            p, ref = ca.SX.sym(f"p{k}", step.p.numel()), ca.SX.sym(f"ref{k}", self.n_x)
            track = ca.SX.sym(f"tr{k}", self.n_x)
            bg, bx = ca.SX.sym(f"bg{k}", self.inequality.size), ca.SX.sym(f"bx{k}", self.n_x)
            nu0, lam0 = ca.SX.sym(f"nu0{k}", self.n_g), ca.SX.sym(f"lam0{k}", self.n_x)
            g, stationarity, comp_g, comp_x = kkt(x, p, w, nu, lam, bg, bx)
            f += TRACKING_SCALE * ca.sum1(track * (x - ref) ** 2)
            f += MULTIPLIER_PROXIMAL * (ca.sumsqr(nu - nu0) + ca.sumsqr(lam - lam0))
            f += rho * (ca.sum1(comp_g) + ca.sum1(comp_x))
            xs += [x, nu, lam]
            ps += [p, ref, track, bg, bx, nu0, lam0]
            cons += [g, stationarity, comp_g, comp_x]
        problem = {"x": ca.vertcat(*xs), "p": ca.vertcat(*ps), "f": f, "g": ca.vertcat(*cons, ca.sumsqr(w) - 1)}
        options = _OPTIONS | {"ipopt.max_iter": max_iterations}
        self.solver = ca.nlpsol("single_level", "ipopt", problem, options)

    @property
    def trial_size(self) -> int:
        """Variables of one trial (step, constraint multipliers, bound multipliers)."""
        return 2 * self.n_x + self.n_g


def _trial_function(step: SymbolicStep, inequality: np.ndarray) -> ca.Function:
    """One trial's constraints, stationarity and complementarity products as a function."""
    w = ca.SX.sym("w", len(step.features))
    nu, lam = ca.SX.sym("nu", step.g.numel()), ca.SX.sym("lam", step.x.numel())
    bg, bx = ca.SX.sym("bg", inequality.size), ca.SX.sym("bx", step.x.numel())
    inner = ca.dot(step.weighted_features, w) + step.regularizer + ca.dot(nu, step.g)
    stationarity = ca.gradient(inner, step.x) + lam
    rows = ca.vertcat(*[step.g[int(i)] for i in inequality]) if inequality.size else ca.SX(0, 1)
    nu_rows = ca.vertcat(*[nu[int(i)] for i in inequality]) if inequality.size else ca.SX(0, 1)
    comp_g = nu_rows * (bg - rows)
    comp_x = lam * (bx - step.x)
    args = [step.x, step.p, w, nu, lam, bg, bx]
    return ca.Function("kkt", args, [step.g, stationarity, comp_g, comp_x])


@lru_cache(maxsize=4)
def _built(step: SymbolicStep, inequality: tuple[int, ...], n_trials: int, max_iterations: int) -> _NLP:
    return _NLP(step, inequality, n_trials, max_iterations)


def _inequality_rows(lbg: np.ndarray, ubg: np.ndarray) -> tuple[int, ...]:
    """The constraint rows that are inequalities (the step problem's structure and the task's
    rules: a given step length makes its row an equality)."""
    return tuple(int(i) for i in np.flatnonzero(lbg != ubg))


@register_algorithm("single-level")
class SingleLevel(IOCAlgorithm):
    """Fit the observation with a step that satisfies the KKT conditions (relaxed complementarity)."""

    description = "single level: one NLP over weights, steps and multipliers, relaxed complementarity driven to 0"
    family = "single-level"
    multi_trial = True
    Config = SingleLevelConfig

    @classmethod
    def prepare(cls) -> None:
        """Build the single-level NLP of the benchmark's one-trial forward problem (about 10 s)."""
        forward = get_forward_problem(WALKER, DEFAULT_INTERVALS)  # as IOCProblem asks for it: one cache entry
        rows = _inequality_rows(*forward.step.constraint_bounds(None, StepRules()))
        _built(forward.step.symbolic, rows, 1, cls.Config().max_iterations)

    def fit(self, problem: IOCProblem) -> IOCResult:
        cfg: SingleLevelConfig = self.config
        trials = problem.trials
        failed = [t.reference() for t in trials if not t.reference().success]
        if failed:
            return _failure(problem, f"failed: projection {failed[0].status}")
        history: list[IterationRecord] = []
        with problem.stats.timed("single_level_start"):
            starts = _starts(problem, cfg, history)
        if not starts:
            return _failure(problem, "failed: no start's forward solve succeeded", history)
        notes: dict = {"solves": [], "runs": []}
        best = None
        for w0, sols0 in starts[: 1 + cfg.restarts]:
            if best is not None and _fits(problem, best[1]):
                break
            w, sols, status = _relaxed_fit(problem, (w0, sols0), cfg, history, notes)
            error = _error(problem, sols)
            notes["runs"].append({"start_weights": [float(v) for v in w0], "tracking_error": error})
            if best is None or error < best[3]:
                best = (w, sols, status, error, w0)
        w, sols, status, _, w0 = best
        notes["start_weights"] = [float(v) for v in w0]
        return _answer(problem, w, sols, history, notes, status)


def _relaxed_fit(problem, start, cfg: SingleLevelConfig, history: list, notes: dict):
    """The relaxation stages from the KKT point ``start`` (weights, forward optima): the
    weights, their forward optima and the status. A start that already reproduces the
    observation (:data:`EXACT_START`) is the answer; an answer that tracks the observation
    worse than its start is replaced by the start (both are verified forward optima)."""
    w, sols = start
    if _error(problem, sols) <= EXACT_START:
        return w, sols, "converged"
    view = problem.trials[0].forward
    nlp = _built(view.symbolic, _inequality_rows(*view.constraint_bounds()), len(problem.trials), cfg.max_iterations)
    duals, converged = None, True
    for t in cfg.relaxation:
        with problem.stats.timed("single_level_nlp"):
            z, duals, done = _stage(nlp, problem.trials, sols, duals, t, cfg, notes["solves"])
        anchored = _anchor(problem, nlp, z, _weights(nlp, view, z), history, notes) if z is not None else None
        if anchored is None or (not done and _error(problem, anchored[1]) >= _error(problem, sols)):
            converged = False
            break
        (w, sols), converged = anchored, converged and done
    if _error(problem, start[1]) < _error(problem, sols):
        notes["start_kept"] = True
        w, sols = start
    return w, sols, "converged" if converged else "max_iterations"


def _fits(problem, sols: list[OracleSolution]) -> bool:
    """Whether the forward optima ``sols`` explain the observation within its noise."""
    return not residual_test(problem.trials, sols, problem.n_features).rejected


def _failure(problem, status: str, history=(), notes=None) -> IOCResult:
    return IOCResult(np.full(problem.n_features, np.nan), status, tuple(history), notes=notes or {})


def _starts(problem, cfg: SingleLevelConfig, history: list) -> list[tuple[np.ndarray, list[OracleSolution]]]:
    """The starts whose forward optima were all solved, lowest tracking error first: the
    uniform and the inverse-KKT weights, and with ``init="best"``, when the better of those
    does not fit the observation, the further starts of :mod:`ioc_bench.ioc.starts`."""
    n = problem.n_features
    candidates = [] if cfg.init == "inverse-kkt" else [np.full(n, 1 / np.sqrt(n))]
    raw = None
    if cfg.init != "uniform":
        kkt = fit_kkt_trials(problem.trials, InverseKKTConfig())
        if kkt.success:
            raw = np.asarray(kkt.weights, dtype=float)
            candidates.append(unit(np.maximum(raw, START_FLOOR)))
    ranked = _solved_starts(problem, cfg, candidates, history)
    if cfg.init == "best" and (not ranked or not _fits(problem, ranked[0][1])):
        more = further_starts(raw if raw is not None else np.ones(n))
        ranked = sorted(ranked + _solved_starts(problem, cfg, more, history), key=lambda s: _error(problem, s[1]))
    kinematics_only = any(t.observed.tau is None for t in problem.trials)
    if (
        cfg.init == "best"
        and cfg.bilevel_start
        and kinematics_only
        and ranked
        and _error(problem, ranked[0][1]) > EXACT_START
    ):
        fitted = _bilevel_start(problem, [w for w, _ in ranked], history)
        ranked = sorted(ranked + fitted, key=lambda s: _error(problem, s[1]))
    return ranked


def _bilevel_start(problem, starts: list[np.ndarray], history: list) -> list[tuple[np.ndarray, list[OracleSolution]]]:
    """Bilevel's fit from the ranked ``starts`` as one more start (none if its forward solves failed)."""
    fitted = refine(problem, starts)
    history.extend(_staged(h, "bilevel-start") for h in (fitted.history if fitted else ()))
    return [(fitted.weights, fitted.solutions)] if fitted else []


def _staged(record: IterationRecord, stage: str) -> IterationRecord:
    """``record`` marked as made in ``stage``."""
    return IterationRecord(
        record.weights,
        tracking_error=record.tracking_error,
        trajectory_error=record.trajectory_error,
        solve_status=record.solve_status,
        extra=record.extra | {"stage": stage},
    )


def _solved_starts(problem, cfg: SingleLevelConfig, candidates: list[np.ndarray], history: list) -> list:
    """Each candidate's forward optima per trial (warm from the reference), the solved ones
    ranked by tracking error."""
    out = []
    for w in candidates:
        sols = [nearest_optimum(t, w, t.reference(), cfg.proximal) for t in problem.trials]
        history.append(IterationRecord.of(problem, w, sols[0] if len(sols) == 1 else sols, stage="start"))
        if all(s.success for s in sols):
            out.append((w, sols))
    return sorted(out, key=lambda s: _error(problem, s[1]))


def _stage(nlp: _NLP, trials, sols, duals, t: float, cfg: SingleLevelConfig, log: list):
    """One solve of the NLP at relaxation ``t``, started at the KKT point ``sols`` (each
    trial's forward optimum and its duals; the candidates for activity are found there) and
    at the NLP's own duals of the last stage: its last iterate (None if not finite), its
    duals (None unless it converged) and whether it converged. A solve that stops at its
    iteration limit is anchored too, and kept only if that lowers the tracking error."""
    args = _arguments(nlp, trials, sols, cfg)
    p = args["p"].copy()
    p[:2] = (t, 0.0) if cfg.complementarity == "scholtes" else (0.0, 1.0 / t)
    lbg, ubg = _comp_bounds(args, t, cfg)
    call = {"x0": args["x0"], "p": p, "lbx": args["lbx"], "ubx": args["ubx"], "lbg": lbg, "ubg": ubg}
    if duals is not None:
        call |= {"lam_x0": duals[0], "lam_g0": duals[1]}
    sol = nlp.solver(**call)
    stats = nlp.solver.stats()
    status = str(stats.get("return_status"))
    log.append({"relaxation": t, "status": status, "iterations": int(stats.get("iter_count", -1))})
    z = np.asarray(sol["x"], dtype=float).ravel()
    if not np.all(np.isfinite(z)):
        return None, None, False
    done = ipopt.converged(status)
    return z, ((np.asarray(sol["lam_x"]).ravel(), np.asarray(sol["lam_g"]).ravel()) if done else None), done


def _comp_bounds(args: dict, t: float, cfg: SingleLevelConfig) -> tuple[np.ndarray, np.ndarray]:
    """The constraint bounds of one solve: Scholtes' products at most ``t``; the penalty's
    rows one-sided at -1, which no product reaches (their signs make them >= 0)."""
    lbg, ubg, rows = args["lbg"].copy(), args["ubg"].copy(), args["comp_rows"]
    if cfg.complementarity == "scholtes":
        ubg[rows] = t
    else:
        lbg[rows], ubg[rows] = -1.0, np.inf
    return lbg, ubg


def _arguments(nlp: _NLP, trials, sols: list[OracleSolution], cfg: SingleLevelConfig) -> dict:
    """Start point, bounds and parameters of one case (the relaxation entries of ``p`` and
    the complementarity rows' upper bounds are set per solve)."""
    view = trials[0].forward
    n_w, cols = nlp.n_w, view.feature_columns
    w0 = np.zeros(n_w)
    w0[cols] = sols[0].weights
    w_hi = np.zeros(n_w)
    w_hi[cols] = np.inf
    parts = {"x0": [w0], "p": [np.zeros(2)], "lbx": [np.zeros(n_w)], "ubx": [w_hi], "lbg": [], "ubg": []}
    comp_rows, sides, offset = [], [], 0
    for trial, sol in zip(trials, sols):
        one = _trial_arguments(nlp, trial, sol, cfg)
        sides.append(one.pop("sides"))
        for key in parts:
            parts[key].extend(one[key])
        comp_rows.append(offset + np.arange(nlp.n_g + nlp.n_x, nlp.n_g + nlp.n_x + nlp.inequality.size + nlp.n_x))
        offset += 2 * nlp.n_x + nlp.n_g + nlp.inequality.size
    parts["lbg"].append([0.0])
    parts["ubg"].append([0.0])
    out = {k: np.concatenate([np.asarray(v, dtype=float).ravel() for v in vs]) for k, vs in parts.items()}
    out["comp_rows"], out["sides"] = np.concatenate(comp_rows), sides
    return out


def _trial_arguments(nlp: _NLP, trial, sol: OracleSolution, cfg: SingleLevelConfig) -> dict:
    """One trial's share of the start, bounds and parameters: multipliers only for the
    inequalities and bounds near activity at the start or at the reference."""
    view = trial.forward
    lbx, ubx = view.variable_bounds()
    lbg, ubg = view.constraint_bounds()
    x0 = np.clip(view.vector(sol.trajectory), lbx, ubx)
    x_ref = view.vector(trial.reference().trajectory)
    near = _near(view, x0, cfg.near_tol), _near(view, x_ref, cfg.near_tol)
    g_lo, g_hi = near[0].g_lower | near[1].g_lower, near[0].g_upper | near[1].g_upper
    x_lo, x_hi = near[0].x_lower | near[1].x_lower, near[0].x_upper | near[1].x_upper
    equality, fixed = lbg == ubg, lbx == ubx
    nu_lo = np.where(equality | g_lo, -np.inf, 0.0)
    nu_hi = np.where(equality | g_hi, np.inf, 0.0)
    lam_lo = np.where(fixed | x_lo, -np.inf, 0.0)
    lam_hi = np.where(fixed | x_hi, np.inf, 0.0)
    lam_g, lam_x = view.duals(sol)
    nu0, lam0 = np.clip(lam_g, nu_lo, nu_hi), np.clip(lam_x, lam_lo, lam_hi)
    ineq = nlp.inequality
    bg = np.where(g_hi[ineq] & ~g_lo[ineq], ubg[ineq], lbg[ineq])
    bx = np.where(x_hi & ~x_lo, ubx, lbx)
    bx = np.where(fixed, x0, bx)
    ref, track = view.tracking_quadratic()
    ref = np.where(track > 0, ref, x0)
    n_c = ineq.size + nlp.n_x
    return {
        "x0": [x0, nu0, lam0],
        "p": [view.parameters(), ref, track, bg, bx, nu0, lam0],
        "lbx": [lbx, nu_lo, lam_lo],
        "ubx": [ubx, nu_hi, lam_hi],
        "lbg": [lbg, np.zeros(nlp.n_x), np.full(n_c, -np.inf)],
        "ubg": [ubg, np.zeros(nlp.n_x), np.zeros(n_c)],
        "sides": (bg, bx),
    }


def _near(view, x: np.ndarray, tol: float):
    return view.active_set(x, tol)


def _weights(nlp: _NLP, view, z: np.ndarray) -> np.ndarray:
    w = np.maximum(z[: nlp.n_w][view.feature_columns], 0.0)
    return w / max(np.linalg.norm(w), 1e-300)


def _trial_point(nlp: _NLP, z: np.ndarray, k: int) -> StartPoint:
    """Trial ``k``'s step and its multipliers, as a forward solve's warm start."""
    base = nlp.n_w + k * nlp.trial_size
    x = z[base : base + nlp.n_x]
    nu = z[base + nlp.n_x : base + nlp.n_x + nlp.n_g]
    lam = z[base + nlp.n_x + nlp.n_g : base + nlp.trial_size]
    return StartPoint(x, lam, nu)


def _error(problem, sols: list[OracleSolution]) -> float:
    """The mean tracking error of one forward optimum per trial."""
    return float(np.mean([t.tracking_error(s.trajectory) for t, s in zip(problem.trials, sols)]))


def _anchor(problem, nlp: _NLP, z: np.ndarray, w: np.ndarray, history: list, notes: dict):
    """The NLP's weights as forward optima, each trial's solve warm from the NLP's step and
    multipliers: an exact KKT point for the next stage (or the answer), or None if a solve
    failed."""
    if not np.any(w > 0):
        return None
    sols = []
    for k, t in enumerate(problem.trials):
        point = _trial_point(nlp, z, k)
        notes.setdefault("nlp_tracking_error", []).append(t.forward.tracking_error(point.x)[0])
        warm = OracleSolution(t.forward.trajectory(point.x), np.zeros(problem.n_features), True, "", 0.0, w, point)
        sols.append(t.optimize(w, start=warm))
    history.append(IterationRecord.of(problem, w, sols[0] if len(sols) == 1 else sols, stage="anchor"))
    return (w, sols) if all(s.success for s in sols) else None


def _answer(problem, w: np.ndarray, sols: list, history: list, notes: dict, status: str) -> IOCResult:
    """The result at forward optima ``sols`` of ``w``: the region and the misfit test from
    their tracking residual."""
    residual, jacobian = tracking_residuals(problem.trials, sols)
    notes["tracking_error"] = float(residual @ residual)
    region = gauss_newton_region(residual, jacobian, w, "Gauss-Newton covariance of the single-level fit's residual")
    fit = residual_test(problem.trials, sols, problem.n_features)
    chosen = _index_of(history, w)
    return IOCResult(w, status, tuple(history), chosen, notes, uncertainty=region, model_fit=fit)


def _index_of(history: list, w: np.ndarray) -> int | None:
    for i in range(len(history) - 1, -1, -1):
        if np.allclose(history[i].weights, w, rtol=0, atol=1e-14):
            return i
    return None
