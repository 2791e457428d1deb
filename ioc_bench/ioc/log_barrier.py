"""The paper's IOC method (Rebula et al., section II.D; SPEC section 3) and its switches.

As printed (the defaults of :class:`LogBarrierConfig`):

1. Draw N trajectories around the observed one with Gaussian noise and project each to
   the feasible set: the suboptimal set X-.
2. Find weights maximising ``sum log(1.5 + w . (phi(x-) - phi(x*)))`` subject to every
   x- costing more than x*, ``|w| = 1`` and ``0.001 < w_i < 0.999``.
3. Optimise a step for the candidate weights (from x*), add it to X-, repeat from 2; stop
   after ``max_iterations``, when the weights stop changing, or when step 2 is infeasible.
4. Output the candidate whose step was closest to the observation.

Each thing that limits it on this walker (docs/ioc.md) has a config switch, so its effect
can be measured alone; :mod:`ioc_bench.ioc.analytic_center` turns them all on.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ioc_bench.ioc.algorithm import IOCAlgorithm, IOCResult, IterationRecord
from ioc_bench.ioc.problem import IOCProblem, OracleSolution
from ioc_bench.ioc.registry import register_algorithm
from ioc_bench.ioc.weight_fit import fit_weights, max_margin
from ioc_bench.trajectory import Observation

#: When the cuts are inconsistent, relax them by this multiple of the smallest relaxation
#: that makes any weights feasible, and take the centre of what remains.
RELAX_FACTOR = 1.5


@dataclass(frozen=True)
class LogBarrierConfig:
    """Settings of the iterative log-barrier IOC. Defaults: the method as printed.

    Attributes:
        n_random: N, projected random trajectories seeding X- (the paper does not say).
        perturbation: their noise, as a fraction of each signal's span.
        max_iterations: candidate weights tried at most (the paper's 25).
        weight_tol: stop when no weight (unit norm) moves more than this.
        offset: the 1.5 inside the log (``objective="paper"``).
        lower, upper: weight bounds (the paper's 0.001 and 0.999).
        objective: ``"paper"`` (``sum log(offset + w.d)``) or ``"center"`` (analytic centre
            of the cone of separating weights).
        scale_features: measure each feature in units of its value at the reference step
            (features here are 1e-4..1e-6, which makes ``log(1.5 + w.d)`` linear).
        forward: ``"plain"``: optimise for the candidate from x*; ``"proximal"``: minimise
            ``w.phi/w.phi(ref) + lambda * distance to ref`` from ref, raising ``lambda``
            through ``proximal`` until the step is cheaper than ref under ``w`` (a cut).
        proximal: the ladder of proximal weights.
        stop_without_cut: stop (converged) when a candidate's step adds no cut.
        cut_tol: a relative cost decrease below this is not a cut.
        reference: ``"observed"``: x* (its features as measured); ``"feasible"``: the
            observation's feasible projection (x* itself when the IOC's model can produce it).
        forward_start: forward solves start at the projected observation ``"warm"`` (its
            primal-dual point: they begin exactly there) or ``"cold"`` (its values with the
            cold-start settings, whose bound push moves them).
        forward_starts: forward solves also try this many - 1 rough guesses with noise and keep
            the cheapest feasible step (the paper's multi-start: 15).
        output: ``"min-error"``: the candidate whose step was closest to the observation
            (the paper); ``"last"``: the last candidate.
    """

    n_random: int = 10
    perturbation: float = 0.05
    max_iterations: int = 25
    weight_tol: float = 1e-4
    offset: float = 1.5
    lower: float = 0.001
    upper: float = 0.999
    objective: str = "paper"
    scale_features: bool = False
    forward: str = "plain"
    proximal: tuple[float, ...] = (30.0, 300.0)
    stop_without_cut: bool = False
    cut_tol: float = 1e-7
    reference: str = "observed"
    forward_start: str = "cold"
    forward_starts: int = 1
    output: str = "min-error"

    def __post_init__(self) -> None:
        if self.n_random < 0 or self.max_iterations < 1 or self.forward_starts < 1:
            raise ValueError("n_random must be >= 0, max_iterations and forward_starts >= 1")
        if not (self.perturbation > 0 and self.weight_tol >= 0 and 0 <= self.lower < self.upper <= 1):
            raise ValueError("perturbation must be > 0, weight_tol >= 0 and 0 <= lower < upper <= 1")
        choices = {
            "objective": ("paper", "center"),
            "forward": ("plain", "proximal"),
            "reference": ("observed", "feasible"),
            "forward_start": ("warm", "cold"),
            "output": ("min-error", "last"),
        }
        for name, valid in choices.items():
            if getattr(self, name) not in valid:
                raise ValueError(f"{name} must be one of {valid}, got {getattr(self, name)!r}")
        if not self.proximal or any(p <= 0 for p in self.proximal):
            raise ValueError("proximal must be a non-empty ladder of positive weights")
        object.__setattr__(self, "proximal", tuple(self.proximal))


def random_samples(problem: IOCProblem, n: int, size: float) -> tuple[list[np.ndarray], int]:
    """Feature vectors of ``n`` projected random perturbations of the observation, and
    how many projections failed (failed ones are left out)."""
    rng = problem.rng(stream=1)
    samples, failed = [], 0
    for _ in range(n):
        sol = problem.project(problem.perturb(rng, size))
        if sol.success:
            samples.append(sol.features)
        else:
            failed += 1
    return samples, failed


@register_algorithm("log-barrier")
class LogBarrier(IOCAlgorithm):
    """Iterative log-barrier IOC; with default config, exactly as the paper prints it."""

    description = "the paper's iterative log-barrier IOC (Rebula et al. 2019), as printed"
    Config = LogBarrierConfig

    def fit(self, problem: IOCProblem) -> IOCResult:
        cfg: LogBarrierConfig = self.config
        reference = self._reference(problem)
        if reference is None:
            return IOCResult(np.full(problem.n_features, np.nan), "failed: the observation could not be projected")
        ref, start = reference
        phi_ref = problem.features_of(ref)
        unit = np.maximum(phi_ref, 1e-3 * phi_ref.max()) if cfg.scale_features else np.ones(problem.n_features)
        samples, failed = random_samples(problem, cfg.n_random, cfg.perturbation)
        n_random = len(samples)
        history: list[IterationRecord] = []
        status, previous, w = "max_iterations", None, None
        for _ in range(cfg.max_iterations):
            fit = self._fit(np.array(samples), phi_ref, unit, previous) if samples else None
            if fit is not None and not fit.success:
                status = "infeasible"
                w = self._relaxed(np.array(samples), phi_ref, unit, previous, w)
                break
            w = fit.weights if fit else _unit(1.0 / unit)
            sol, extra = self._forward(problem, w, start, phi_ref)
            history.append(_record(problem, w, sol, phi_ref, **extra))
            if sol.success:
                samples.append(sol.features)
            if cfg.stop_without_cut and not history[-1].extra["cost_gap"] < -cfg.cut_tol:
                status = "converged"  # no cheaper step near the reference: w is consistent with it
                break
            if previous is not None and np.max(np.abs(w - previous)) < cfg.weight_tol:
                status = "converged"
                break
            previous = w
        return self._result(problem, history, status, w, {"random_samples": n_random, "failed_projections": failed})

    # -- steps ------------------------------------------------------------------------------
    def _reference(self, problem: IOCProblem) -> tuple[Observation, OracleSolution] | None:
        """The step candidates are compared with (x*, or its feasible projection), and the
        projection, from which forward solves start."""
        projected = problem.reference()
        if not projected.success:
            return None
        observed = self.config.reference == "observed" and problem.observed.tau is not None
        return (problem.observed if observed else projected.trajectory), projected

    def _fit(self, samples: np.ndarray, phi_ref: np.ndarray, unit: np.ndarray, previous):
        """Weights from the samples (step 2), in raw units."""
        cfg = self.config
        start = None if previous is None else previous * unit
        fit = fit_weights((samples - phi_ref) / unit, cfg.objective, cfg.offset, cfg.lower, cfg.upper, start)
        return type(fit)(_unit(fit.weights / unit), fit.success, fit.status, fit.min_margin)

    def _relaxed(self, samples, phi_ref, unit, previous, current):
        """When no weights separate the samples: the centre of the cone relaxed just enough
        to be non-empty (``objective="center"``); the paper's method keeps its last candidate."""
        cfg = self.config
        if cfg.objective == "paper":
            return current
        d = (samples - phi_ref) / unit
        start = None if previous is None else previous * unit
        relax = RELAX_FACTOR * max(-max_margin(d, cfg.lower, cfg.upper, start), 0.0)
        fit = fit_weights(d, "center", lower=cfg.lower, upper=cfg.upper, start=start, relax=relax)
        return _unit(fit.weights / unit) if fit.success else current

    def _forward(self, problem: IOCProblem, w: np.ndarray, start: OracleSolution, phi_ref: np.ndarray):
        """The candidate's step (step 3): plain, or proximal until it cuts."""
        cfg = self.config
        begin = start if cfg.forward_start == "warm" else start.trajectory
        if cfg.forward == "plain":
            return problem.optimize(w, start=begin, starts=cfg.forward_starts), {}
        for lam in cfg.proximal:
            sol = problem.optimize(w, start=start, proximal=lam, anchor=start.trajectory)
            if sol.success and w @ (sol.features - phi_ref) < -cfg.cut_tol * (w @ phi_ref):
                break
        return sol, {"proximal": lam}

    def _result(self, problem, history, status, w, notes) -> IOCResult:
        """Step 4: pick the output among the candidates."""
        if w is None:
            return IOCResult(np.full(problem.n_features, np.nan), f"failed: {status} before the first candidate")
        if self.config.output == "last" or not any(np.isfinite(h.tracking_error) for h in history):
            return IOCResult(w, status, tuple(history), len(history) - 1, notes)
        chosen = int(np.nanargmin([h.tracking_error for h in history]))
        return IOCResult(np.array(history[chosen].weights), status, tuple(history), chosen, notes)


def _record(problem: IOCProblem, w: np.ndarray, sol: OracleSolution, phi_ref: np.ndarray, **extra) -> IterationRecord:
    """The history entry of one candidate and its forward solve; ``cost_gap`` is
    ``w . (phi(x_w) - phi(x*)) / w . phi(x*)``: negative when the new step is cheaper than the
    observation under the candidate (the sample cuts it off), >= 0 when it adds nothing."""
    gap = float(w @ (sol.features - phi_ref) / (w @ phi_ref)) if sol.success else float("nan")
    return IterationRecord.of(problem, w, sol, cost_gap=gap, **extra)


def _unit(w: np.ndarray) -> np.ndarray:
    return w / np.linalg.norm(w)
