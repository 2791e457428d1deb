"""Bilevel IOC: the weights whose optimal step best matches the observation.

The classic bilevel formulation of IOC (Mombaur, Truong & Laumond 2010): an outer search
over the weights minimises the distance between the forward problem's optimum ``x*(w)`` and
the observation. The distance is a sum of squares, ``D = |r(w)|^2`` with ``r`` the
span-normalised differences of every measured signal, so the outer problem is a nonlinear
least-squares problem. Its Jacobian ``dr/dw`` comes from the implicit-function theorem at
each optimum (``problem.forward.sensitivity``: the KKT system with the active set held
fixed), as in Pontryagin Differentiable Programming (Jin, Wang, Yang & Mou, NeurIPS 2020)
and IDOC (Xu, Molloy & Gould, ICLR 2024). The default method exploits that structure:

- **Gauss-Newton** (a trust-region reflective least-squares solver, ``scipy.optimize.
  least_squares``): one forward solve and one sensitivity per iteration, the Jacobian
  ``dr/dw`` exact, converging in a few iterations where L-BFGS-B on ``D`` needed 20-50;
- **started where data and model agree**: from the better (lower ``D``) of the uniform
  weights and the inverse-KKT weights at the feasible reference;
- **every forward solve warm-started at the reference** (its primal-dual point), so that
  ``x*(w)`` is the optimum in the observation's basin whatever path the search took
  (warm-starting from the last optimum made the objective depend on the path: measured
  with one-start demonstrations, penalize-knee 0.041 against 3e-6);
- **distractors**: with more features than the cost has, an L1 path, as the paper suggests
  ("an L1 norm error term on the weights could be used to find sparse cost functions"):
  ``D + lambda sum(w)`` (``w >= 0`` with ``|w| = 1``, so the term prefers weight on fewer
  features) for ``lambda`` rising from 0, each fit warm from the last, and the Bayesian
  information criterion ``m log D + k log m`` (``m`` measured signal values, ``k`` weights
  above :data:`ACTIVE_WEIGHT`) chooses along the path;
- **a 95 % region** for the weights: the Gauss-Newton covariance ``s^2 (J^T J)^{-1}`` of the
  fit in the tangent space of the unit sphere, ``s^2`` the residual variance, mapped to each
  unit-norm weight (``w_i +- 1.96 sd_i``, at least the weights' resolution, clipped to [0, 1];
  :func:`~ioc_bench.ioc.inverse_kkt.interval`).

The weights are ``w = u / |u|`` with ``u >= floor``. ``method="lbfgs"`` keeps the previous
built-in (L-BFGS-B on ``D``, uniform start) selectable for comparison.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np
from scipy.optimize import least_squares, minimize

from ioc_bench.ioc.algorithm import IOCAlgorithm, IOCResult, IterationRecord, WeightRegion
from ioc_bench.ioc.inverse_kkt import InverseKKTConfig, fit_kkt_trials, interval
from ioc_bench.ioc.misfit import residual_test
from ioc_bench.ioc.nearest_optimum import nearest_optimum
from ioc_bench.ioc.oracle import OracleSolution
from ioc_bench.ioc.problem import IOCProblem
from ioc_bench.ioc.registry import register_algorithm
from ioc_bench.ioc.starts import further_starts, unit
from ioc_bench.validation import check_non_negative

#: Tracking error given to the search for a candidate whose forward solve failed (it backtracks).
FAILED_SOLVE_ERROR = 1e3
#: A tracking error below this is an exact fit (the forward solves' own precision is ~1e-8
#: in each signal, 1e-16 in the error): nothing is left to fit.
EXACT_FIT = 1e-14
#: A weight below this (unit norm) counts as zero in the L1 path's information criterion.
ACTIVE_WEIGHT = 1e-3


#: Default ``ftol`` per method (see :class:`BilevelConfig`).
FTOL = {"gauss-newton": 1e-4, "lbfgs": 1e-10}


@dataclass(frozen=True)
class BilevelConfig:
    """Settings of the bilevel search.

    Attributes:
        method: ``"gauss-newton"`` (least squares with the sensitivity Jacobian) or
            ``"lbfgs"`` (L-BFGS-B on the tracking error, with the gradient from the same Jacobian).
        max_iterations: outer iterations at most (per fit of the L1 path).
        max_solves: forward solves at most, in all.
        gtol: stop when the projected gradient is below this (L-BFGS-B; Gauss-Newton: the
            scaled gradient).
        ftol: stop when the tracking error improves by less than this (relative; None:
            the method's own, :data:`FTOL`). Gauss-Newton: 1e-4, a tenth of what
            estimating 2 free weights from ~1400 noisy signal values moves the tracking
            error (2/1400); past it the steps change nothing the noise lets one tell apart.
            Under noise the fit converges linearly (a large-residual least-squares problem,
            ratio about 0.6 per step on penalize-dtau, seed 0), so a smaller tolerance buys
            solves, not accuracy (1e-6: 32 solves for a weight change of 3e-4 in the last
            20), and far below the solves' own 1e-8 jitter (1e-10) an exact fit iterates
            until its budget runs out. L-BFGS-B: 1e-10, because its steps are not
            Gauss-Newton steps (with 1e-4 it stops after 3 solves at a weight error of 0.46
            on an exact penalize-knee observation).
        xtol: Gauss-Newton: stop when the weights move by less than this (relative; below
            the weights' resolution, 1e-3).
        floor: lower bound on each unnormalised weight (keeps ``|u|`` away from 0).
        initial_scale: ``|u|`` at the start (L-BFGS-B: its first step is a unit step in u).
        start: where forward solves start: ``"reference"`` (the feasible reference, every
            time) or ``"best"`` (the best optimum so far).
        proximal: on an observation without torques, if > 0, each forward solve is also
            made through a proximal step of this weight towards the reference, and the
            optimum nearer the observation kept (:func:`~ioc_bench.ioc.nearest_optimum.
            nearest_optimum`: a solve straight from a reference whose torques were inferred
            can reach another optimum, one the data reject). Three solves instead of one;
            0: straight from the start only.
        init: where the weights start: ``"best"`` (see :mod:`ioc_bench.ioc.starts`: the lower tracking
            error of uniform and inverse-KKT weights, and more starts when neither fits),
            ``"uniform"`` or ``"inverse-kkt"``.
        restarts: with ``init="best"``, Gauss-Newton fits from this many more of the ranked
            starts when a fit's residual is more than noise (the misfit test); the fit with
            the lowest tracking error is kept.
        l1_path: the L1 path's lambdas, relative to the unpenalised fit's tracking error
            (used only when the problem offers features beyond the cost features; empty: off).
    """

    method: str = "gauss-newton"
    max_iterations: int = 30
    max_solves: int = 60
    gtol: float = 1e-9
    ftol: float | None = None
    xtol: float = 1e-4
    floor: float = 1e-6
    initial_scale: float = 10.0
    start: str = "reference"
    proximal: float = 0.0
    init: str = "best"
    restarts: int = 1
    l1_path: tuple[float, ...] = (0.01, 0.1, 1.0)

    def __post_init__(self) -> None:
        positive = self.gtol > 0 and self.tolerance > 0 and self.xtol > 0 and self.floor > 0 and self.initial_scale > 0
        if self.method not in ("gauss-newton", "lbfgs"):
            raise ValueError(f"method must be 'gauss-newton' or 'lbfgs', got {self.method!r}")
        if self.start not in ("reference", "best"):
            raise ValueError(f"start must be 'reference' or 'best', got {self.start!r}")
        if self.init not in ("best", "uniform", "inverse-kkt"):
            raise ValueError(f"init must be 'best', 'uniform' or 'inverse-kkt', got {self.init!r}")
        if self.max_iterations < 1 or self.max_solves < 1 or not positive:
            raise ValueError("max_iterations and max_solves must be >= 1; gtol, ftol, floor and initial_scale > 0")
        check_non_negative(self.proximal, "proximal")
        if self.restarts < 0:
            raise ValueError("restarts must be >= 0")
        if any(not lam > 0 for lam in self.l1_path):
            raise ValueError("l1_path lambdas must be > 0")

    @property
    def tolerance(self) -> float:
        """The relative improvement of the tracking error below which the fit stops."""
        return FTOL[self.method] if self.ftol is None else self.ftol


class _Budget(Exception):
    """The forward-solve budget is spent."""


@dataclass(frozen=True, eq=False)
class _Trial:
    """What the fit needs of one trial: its problem, warm start and measured signal values."""

    problem: IOCProblem
    start: OracleSolution
    rows: np.ndarray
    ref: np.ndarray
    sqrt_w: np.ndarray

    @classmethod
    def of(cls, problem: IOCProblem) -> _Trial:
        ref, weight = problem.forward.tracking_quadratic()
        rows = np.flatnonzero(weight > 0)
        return cls(problem, problem.reference(), rows, ref[rows], np.sqrt(weight[rows]))


class _Fit:
    """The residuals of candidate weights and their Jacobian, one forward solve per candidate
    and trial (stacked over the trials of a multi-trial problem), keeping the history, the
    best candidate and the warm starts."""

    def __init__(self, problem: IOCProblem, cfg: BilevelConfig):
        self.problem, self.cfg = problem, cfg
        self.trials = [_Trial.of(t) for t in problem.trials]
        self.history: list[IterationRecord] = []
        self.best: tuple[float, np.ndarray] = (np.inf, np.full(problem.n_features, np.nan))
        self._cache: dict[bytes, tuple[np.ndarray, list[OracleSolution]]] = {}

    @property
    def m(self) -> int:
        return sum(t.rows.size for t in self.trials)

    def solve(self, w: np.ndarray) -> tuple[np.ndarray, list[OracleSolution]]:
        """Residuals (m,) of unit weights ``w`` and each trial's forward solution (cached)."""
        key = np.round(w, 14).tobytes()
        if key in self._cache:
            return self._cache[key]
        if len(self.history) >= self.cfg.max_solves:
            raise _Budget
        sols = [self._optimum(t, w) for t in self.trials]
        parts = []
        for t, sol in zip(self.trials, sols):
            if sol.success:
                parts.append(t.sqrt_w * (t.problem.forward.vector(sol.trajectory)[t.rows] - t.ref))
            else:
                parts.append(np.full(t.rows.size, np.sqrt(FAILED_SOLVE_ERROR / self.m)))
        r = np.concatenate(parts)
        error = float(r @ r)
        self.history.append(IterationRecord.of(self.problem, w, sols[0] if len(sols) == 1 else sols))
        if error < self.best[0]:
            self.best = (error, w)
            if self.cfg.start == "best" and all(s.success for s in sols):
                self.trials = [replace(t, start=s) for t, s in zip(self.trials, sols)]
        self._cache[key] = (r, sols)
        return r, sols

    def _optimum(self, trial: _Trial, w: np.ndarray) -> OracleSolution:
        """The forward optimum of ``w`` for one trial, from its start."""
        return nearest_optimum(trial.problem, w, trial.start, self.cfg.proximal)

    def jacobian(self, w: np.ndarray) -> np.ndarray:
        """(m, F) derivative of the residuals by the weights (zero where a solve failed)."""
        _, sols = self.solve(w)
        blocks = []
        for t, sol in zip(self.trials, sols):
            if sol.success:
                blocks.append(t.sqrt_w[:, None] * t.problem.forward.sensitivity(sol)[t.rows])
            else:
                blocks.append(np.zeros((t.rows.size, w.size)))
        return np.vstack(blocks)


@register_algorithm("bilevel")
class Bilevel(IOCAlgorithm):
    """Fit the optimum of the weights to the observation (Gauss-Newton with KKT sensitivities)."""

    description = "bilevel: Gauss-Newton on the optimum's tracking error, Jacobian from the KKT sensitivity"
    family = "bilevel"
    multi_trial = True
    Config = BilevelConfig

    def fit(self, problem: IOCProblem) -> IOCResult:
        cfg: BilevelConfig = self.config
        if not all(t.reference().success for t in problem.trials):
            return IOCResult(np.full(problem.n_features, np.nan), "failed: the observation could not be projected")
        fit = _Fit(problem, cfg)
        path: list = []
        try:
            starts = self._initial(problem, fit)
            if cfg.method == "lbfgs":
                status, message = _lbfgs(fit, starts[0])
                w = fit.best[1]
            else:
                w, status, message, path = _best_of_starts(problem, fit, starts)
        except _Budget:
            status, message = "max_iterations", f"forward-solve budget ({cfg.max_solves}) spent"
            w = fit.best[1]
        if np.all(np.isfinite(w)) and not _solved(fit, w) and _solved(fit, fit.best[1]):
            # A step may end where the forward solve fails (its residual is only a penalty):
            # that is no answer, so the best candidate whose solves succeeded is returned.
            w, message = fit.best[1], f"{message}; the last weights' forward solve failed, the best solved ones kept"
        error = fit.best[0] if cfg.method == "lbfgs" or status == "max_iterations" else _error(fit, w)
        if not np.isfinite(error) or not np.all(np.isfinite(w)) or not _solved(fit, w):
            return IOCResult(
                np.full(problem.n_features, np.nan), "failed: no forward solve succeeded", tuple(fit.history)
            )
        notes = {"tracking_error": error, "message": message}
        if path:
            notes["l1_path"] = path
        chosen = _index_of(fit, w)
        _, sols = fit.solve(w)
        fitted = residual_test(problem.trials, sols, problem.n_features)
        return IOCResult(w, status, tuple(fit.history), chosen, notes, uncertainty=_region(fit, w), model_fit=fitted)

    def _initial(self, problem: IOCProblem, fit: _Fit) -> list[np.ndarray]:
        """The starts, best (lowest tracking error) first."""
        cfg: BilevelConfig = self.config
        uniform = np.full(problem.n_features, 1 / np.sqrt(problem.n_features))
        if cfg.init == "uniform" or cfg.method == "lbfgs":
            return [uniform]
        with problem.stats.timed("kkt_fit"):
            kkt = fit_kkt_trials(problem.trials, InverseKKTConfig())
        raw = kkt.weights if kkt.success else uniform
        candidate = unit(np.maximum(raw, cfg.floor))
        if cfg.init == "inverse-kkt":
            return [candidate]
        ranked = sorted((candidate, uniform), key=lambda w: _error(fit, w))
        if _error(fit, ranked[0]) <= EXACT_FIT or _fits(problem, fit, ranked[0]):
            return ranked
        return sorted(ranked + further_starts(raw), key=lambda w: _error(fit, w))


@dataclass(frozen=True)
class Refined:
    """A Gauss-Newton fit from given weights: the weights, each trial's forward optimum, the
    status and message of the fit and its candidates."""

    weights: np.ndarray
    solutions: list[OracleSolution]
    status: str
    message: str
    history: tuple[IterationRecord, ...]


def refine(problem: IOCProblem, starts: list[np.ndarray], config: BilevelConfig | None = None) -> Refined | None:
    """Bilevel's fit from the given weights, best first: Gauss-Newton from the first, and from
    the next ones (up to ``restarts``) while the fit is more than noise, every forward solve
    from the observation's projection; the fit with the lowest tracking error. Another
    method's starts fitted as ``bilevel`` fits them. None when no forward solve succeeded."""
    cfg = config or BilevelConfig()
    fit = _Fit(problem, cfg)
    floored = [unit(np.maximum(np.asarray(w, dtype=float), cfg.floor)) for w in starts]
    try:
        w, status, message, _ = _best_of_starts(problem, fit, floored)
    except _Budget:
        w, status, message = fit.best[1], "max_iterations", f"forward-solve budget ({cfg.max_solves}) spent"
    if not _solved(fit, w):
        w = fit.best[1]
    if not _solved(fit, w):
        return None
    return Refined(w, fit.solve(w)[1], status, message, tuple(fit.history))


def _fits(problem: IOCProblem, fit: _Fit, w: np.ndarray) -> bool:
    """Whether the optimum of ``w`` explains the observation within its noise (every trial solved)."""
    _, sols = fit.solve(w)
    return all(s.success for s in sols) and not residual_test(problem.trials, sols, problem.n_features).rejected


def _best_of_starts(problem: IOCProblem, fit: _Fit, starts: list[np.ndarray]) -> tuple[np.ndarray, str, str, list]:
    """Gauss-Newton from the best start, and from the next ones (up to ``restarts``) while the
    fit is more than noise; the fit with the lowest tracking error."""
    best = _gauss_newton_path(problem, fit, starts[0])
    for w0 in starts[1 : 1 + fit.cfg.restarts]:
        if _fits(problem, fit, best[0]) or _error(fit, w0) >= FAILED_SOLVE_ERROR:
            break
        again = _gauss_newton_path(problem, fit, w0)
        if _error(fit, again[0]) < _error(fit, best[0]):
            best = again
    return best


def _solved(fit: _Fit, w: np.ndarray) -> bool:
    """Whether every trial's forward solve at ``w`` succeeded (cached solves are reused)."""
    if not np.all(np.isfinite(w)):
        return False
    try:
        _, sols = fit.solve(w)
    except _Budget:
        return False
    return all(sol.success for sol in sols)


def _error(fit: _Fit, w: np.ndarray) -> float:
    r, _ = fit.solve(w)
    return float(r @ r)


def _index_of(fit: _Fit, w: np.ndarray) -> int | None:
    for i, h in enumerate(fit.history):
        if np.allclose(h.weights, w, rtol=0, atol=1e-14):
            return i
    return None


def _gauss_newton(fit: _Fit, w0: np.ndarray, lam: float, scale: float) -> tuple[np.ndarray, bool, str]:
    """One least-squares fit of ``D(w) + lam * scale * sum(w)`` from ``w0`` over ``u >= floor``."""
    cfg = fit.cfg
    n = w0.size
    if lam == 0 and _error(fit, w0) <= EXACT_FIT:
        return w0, True, "the start reproduces the observation to the solves' precision"

    def residuals(u: np.ndarray) -> np.ndarray:
        w = unit(u)
        r, _ = fit.solve(w)
        extra = [np.sqrt(lam * scale * w.sum())] if lam > 0 else []
        return np.concatenate([r, extra, [np.linalg.norm(u) - 1.0]])  # the last fixes the scale of u

    def jacobian(u: np.ndarray) -> np.ndarray:
        norm = np.linalg.norm(u)
        w = u / norm
        dw_du = (np.eye(n) - np.outer(w, w)) / norm
        rows = [fit.jacobian(w) @ dw_du]
        if lam > 0:
            rows.append((np.sqrt(lam * scale) / (2 * np.sqrt(w.sum())) * dw_du.sum(axis=0))[None, :])
        rows.append((u / norm)[None, :])
        return np.vstack(rows)

    res = least_squares(
        residuals,
        np.maximum(w0, cfg.floor),
        jac=jacobian,
        bounds=(cfg.floor, np.inf),
        method="trf",
        ftol=cfg.tolerance,
        xtol=cfg.xtol,
        gtol=cfg.gtol,
        max_nfev=cfg.max_iterations,
        x_scale="jac",
    )
    return unit(res.x), bool(res.success), str(res.message)


def _gauss_newton_path(problem: IOCProblem, fit: _Fit, w0: np.ndarray) -> tuple[np.ndarray, str, str, list]:
    """The unpenalised fit, then (with distractor features) the L1 path, chosen by BIC."""
    w, ok, message = _gauss_newton(fit, w0, 0.0, 1.0)
    base = _error(fit, w)
    path = [{"lambda": 0.0, "weights": w.tolist(), "tracking_error": base, "bic": _bic(fit, w)}]
    if _has_distractors(problem) and fit.cfg.l1_path:
        scale = max(base, 1e-12)
        current = w
        for lam in fit.cfg.l1_path:
            current, _, _ = _gauss_newton(fit, current, lam, scale)
            path.append(
                {
                    "lambda": lam,
                    "weights": current.tolist(),
                    "tracking_error": _error(fit, current),
                    "bic": _bic(fit, current),
                }
            )
        best = min(path, key=lambda p: p["bic"])
        w = np.array(best["weights"])
    return w, "converged" if ok else "max_iterations", message, path


def _has_distractors(problem: IOCProblem) -> bool:
    """Whether the problem weighs a feature that is no effort (an ankle's effort is one)."""
    from ioc_bench.features import efforts

    return len(efforts(problem.features)) < len(problem.features)


def _bic(fit: _Fit, w: np.ndarray) -> float:
    """Bayesian information criterion of a fit: ``m log(D / m) + k log m``."""
    d = max(_error(fit, w), 1e-300)
    k = int(np.sum(w > ACTIVE_WEIGHT))
    return float(fit.m * np.log(d / fit.m) + k * np.log(fit.m))


def _region(fit: _Fit, w: np.ndarray) -> WeightRegion | None:
    """The Gauss-Newton 95 % region of the unit-norm weights at ``w`` (None without a Jacobian)."""
    r, sols = fit.solve(w)
    if not all(s.success for s in sols):
        return None
    jac = fit.jacobian(w)
    basis = np.linalg.svd(np.eye(w.size) - np.outer(w, w))[0][:, : w.size - 1]  # the sphere's tangent space
    jt = jac @ basis
    dof = max(fit.m - (w.size - 1), 1)
    variance = float(r @ r) / dof
    cov_t = variance * np.linalg.pinv(jt.T @ jt)
    cov = basis @ cov_t @ basis.T
    lower, upper = interval(w, np.sqrt(np.maximum(np.diag(cov), 0.0)))
    cov = (cov + cov.T) / 2
    return WeightRegion(
        tuple(lower),
        tuple(upper),
        0.95,
        tuple(map(tuple, cov)),
        "Gauss-Newton covariance of the fit, residual variance",
    )


def _lbfgs(fit: _Fit, w0: np.ndarray) -> tuple[str, str]:
    """L-BFGS-B on the tracking error from ``w0``, the gradient through ``w = u / |u|``."""
    cfg = fit.cfg

    def objective(u: np.ndarray) -> tuple[float, np.ndarray]:
        norm = float(np.linalg.norm(u))
        w = u / norm
        r, _ = fit.solve(w)
        grad_w = 2 * r @ fit.jacobian(w)
        return float(r @ r), (grad_w - w * (w @ grad_w)) / norm  # through w = u / |u|

    u0 = w0 * cfg.initial_scale
    options = {"maxiter": cfg.max_iterations, "gtol": cfg.gtol, "ftol": cfg.tolerance}
    res = minimize(objective, u0, jac=True, method="L-BFGS-B", bounds=[(cfg.floor, None)] * u0.size, options=options)
    return ("converged" if res.success else "max_iterations"), str(res.message)
