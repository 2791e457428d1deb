"""The iterative cutting-plane loop of the paper's IOC, composed from small named strategies.

The loop (Rebula et al., section II.D): a reference step and its features, a set of
suboptimal samples, then repeatedly a weight step (weights under which every sample costs
more than the reference) and a forward step (the optimal step for those weights, which
becomes a new sample: a cut). What varies between methods is each strategy:

- :class:`ReferenceChoice`: what the candidates are compared with (x* as observed, or its
  feasible projection);
- a weight step (:class:`LogBarrierStep`, :class:`AnalyticCentreStep`);
- a forward step (:class:`PlainForward`, :class:`ProximalForward`);
- the output rule (:class:`MinErrorOutput`, :class:`LastOutput`).

A variant is a composition (see ``log_barrier.py`` and ``analytic_center.py``), not a flag.

Samples whose features differ from the reference's by less than ``cut_threshold``
(relative) are not cuts: such a step is the reference again, to solver tolerance, and
normalising its difference would cut in a random direction. And a cut only excludes
weights under which the sample is cheaper than the reference by more than that tolerance
(``w . phi(x_i) >= (1 - cut_threshold) w . phi(ref)``): the reference is optimal only to it
(demonstrations are verified to 1e-6; measured: with exact cuts, an ideal penalize-knee
case cut off the truth after 8 cuts and ended infeasible at 0.0013 weight error). The loop stops after
``max_iterations``, when the weights move less than ``weight_tol``, when no weights
separate the samples (``infeasible``), or when a forward solve fails (``forward_failed``,
the paper's "until the optimization fails to find a solution"); with ``stop_without_cut``
also when a candidate's step adds no cut (``converged``: the candidate is consistent).
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Any, Protocol

import numpy as np

from ioc_bench.ioc.algorithm import IOCResult, IterationRecord, WeightRegion
from ioc_bench.ioc.cut_region import cut_region
from ioc_bench.ioc.oracle import OracleSolution
from ioc_bench.ioc.problem import IOCProblem
from ioc_bench.ioc.weight_fit import best_separating, fit_weights, max_margin
from ioc_bench.trajectory import Observation
from ioc_bench.weights import normalize

#: When the cuts are inconsistent, relax them by this multiple of the smallest relaxation
#: that makes any weights feasible, and take the centre of what remains.
RELAX_FACTOR = 1.5


@dataclass(frozen=True)
class ReferenceChoice:
    """Which step candidates are compared with, and where forward steps start. Called on a
    problem, it gives the chosen reference step and the observation's projection (``None``
    when the projection failed).

    Attributes:
        use: ``"observed"``: x* with its features as measured (the paper); ``"projected"``:
            the observation's feasible projection (x* itself when the model can produce it).
    """

    use: str = "observed"

    def __call__(self, problem: IOCProblem) -> tuple[Observation, OracleSolution] | None:
        projected = problem.reference()
        if not projected.success:
            return None
        observed = self.use == "observed" and problem.observed.tau is not None
        return (problem.observed if observed else projected.trajectory), projected


class WeightStep(Protocol):
    """Weights from the feature differences ``d_i = phi(x_i) - phi(ref)`` of the samples."""

    lower: float

    def fit(self, diffs: np.ndarray, previous: np.ndarray | None) -> tuple[np.ndarray, bool]: ...

    def relaxed(self, diffs: np.ndarray, previous: np.ndarray | None, current: np.ndarray | None) -> np.ndarray: ...


@dataclass(frozen=True)
class LogBarrierStep:
    """The paper's weight step: ``max sum log(offset + w . d_i)`` s.t. ``w . d_i > 0``,
    ``|w| = 1``, ``lower < w < upper`` (raw feature units).

    The paper stops when the step is infeasible. Before the first candidate that would end
    the method with no answer at all, which is what an observation that is no optimum of
    the model gives (a person's step: some projected perturbations of it cost less under
    every weight vector). Then the first candidate is the weights that come nearest to
    separating every sample (the largest smallest scaled separation,
    :func:`~ioc_bench.ioc.weight_fit.best_separating`), and the method goes on as printed.
    """

    offset: float = 1.5
    lower: float = 0.001
    upper: float = 0.999

    def fit(self, diffs, previous):
        fit = fit_weights(diffs, "paper", self.offset, self.lower, self.upper, previous)
        if fit.success or previous is not None:
            return fit.weights, fit.success
        w = best_separating(diffs, self.lower, self.upper)
        return w, bool(np.all(np.isfinite(w)))

    def relaxed(self, diffs, previous, current):
        return current  # the paper keeps its last candidate


@dataclass(frozen=True)
class AnalyticCentreStep:
    """The analytic centre of the cone of separating weights, in features measured in units
    of their value at the reference (``unit``); when the cone is empty, the centre of the
    cone relaxed just enough to be non-empty."""

    unit: np.ndarray
    lower: float = 0.0
    upper: float = 1.0

    def fit(self, diffs, previous):
        start = None if previous is None else previous * self.unit
        fit = fit_weights(diffs / self.unit, "center", lower=self.lower, upper=self.upper, start=start)
        return normalize(fit.weights / self.unit), fit.success

    def relaxed(self, diffs, previous, current):
        d = diffs / self.unit
        start = None if previous is None else previous * self.unit
        relax = RELAX_FACTOR * max(-max_margin(d, self.lower, self.upper, start), 0.0)
        fit = fit_weights(d, "center", lower=self.lower, upper=self.upper, start=start, relax=relax)
        return normalize(fit.weights / self.unit) if fit.success else current


@dataclass(frozen=True)
class PlainForward:
    """The optimal step for the candidate: from the projected reference, ``"warm"`` (its
    primal-dual point: the solve begins exactly there) or ``"cold"`` (its values with the
    cold-start settings), keeping the best of ``starts`` (the paper's multi-start: 15)."""

    start: str = "warm"
    starts: int = 1

    def __call__(self, problem, w, start, phi_ref, cut_threshold) -> tuple[OracleSolution, dict[str, Any]]:
        begin = start if self.start == "warm" else start.trajectory
        return problem.optimize(w, start=begin, starts=self.starts), {}


@dataclass(frozen=True)
class ProximalForward:
    """A step held near the reference: ``min w.phi/w.phi(ref) + lambda D(x, ref)`` from the
    reference, ``lambda`` going through ``ladder`` until the step is cheaper (a cut)."""

    ladder: tuple[float, ...] = (30.0, 300.0)

    def __call__(self, problem, w, start, phi_ref, cut_threshold):
        for lam in self.ladder:
            sol = problem.optimize(w, start=start, proximal=lam, anchor=start.trajectory)
            if sol.success and w @ (sol.features - phi_ref) < -cut_threshold * (w @ phi_ref):
                break
        return sol, {"proximal": lam}


def min_error_output(history: list[IterationRecord], last: np.ndarray) -> tuple[np.ndarray, int | None]:
    """The paper's output: the candidate whose step was closest to the observation."""
    errors = [h.tracking_error for h in history]
    if not np.any(np.isfinite(errors)):
        return last, len(history) - 1 if history else None
    chosen = int(np.nanargmin(errors))
    return np.array(history[chosen].weights), chosen


def last_output(history: list[IterationRecord], last: np.ndarray) -> tuple[np.ndarray, int | None]:
    """A cutting-plane method's output: the last candidate (or centre)."""
    return last, len(history) - 1 if history else None


@dataclass(frozen=True)
class CuttingPlane:
    """One composition of the loop (see the module docstring).

    Attributes:
        reference: the reference strategy.
        weight_step: the weight step (built per problem: it may scale by the reference).
        forward: the forward step.
        output: the output rule.
        n_random: projected random perturbations of the observation seeding the samples.
        perturbation: their noise, as a fraction of each signal's span.
        max_iterations: candidates tried at most.
        weight_tol: stop when no weight (unit norm) moves more than this.
        cut_threshold: relative feature difference (and cost decrease) below which a sample
            is the reference again, not a cut.
        stop_without_cut: stop when a candidate's step adds no cut.
    """

    reference: ReferenceChoice
    weight_step: Any
    forward: Any
    output: Any
    n_random: int
    perturbation: float
    max_iterations: int
    weight_tol: float
    cut_threshold: float
    stop_without_cut: bool

    def run(self, problem: IOCProblem) -> IOCResult:
        """Run the loop on ``problem``; on a multi-trial problem every trial gets its own
        reference, samples and forward step, and one weight step separates them all."""
        trials = problem.trials
        refs = [self.reference(t) for t in trials]
        if any(r is None for r in refs):
            return IOCResult(np.full(problem.n_features, np.nan), "failed: the observation could not be projected")
        starts = [start for _, start in refs]
        phi_refs = [t.features_of(observed) for t, (observed, _) in zip(trials, refs)]
        step = self.weight_step(np.mean(phi_refs, axis=0)) if callable(self.weight_step) else self.weight_step
        samples, notes = self._samples(trials, phi_refs)
        history: list[IterationRecord] = []
        status, previous, w = "max_iterations", None, None
        for _ in range(self.max_iterations):
            # A cut keeps the weights under which the sample costs at least (1 - cut_threshold)
            # times the reference: the reference is optimal only to that tolerance.
            diffs = self._diffs(samples, phi_refs)
            if diffs is None:
                w = normalize(1.0 / getattr(step, "unit", np.ones(problem.n_features)))
            else:
                w, ok = step.fit(diffs, previous)
                if not ok:
                    status, w = "infeasible", step.relaxed(diffs, previous, previous)
                    break
            steps = [self.forward(t, w, s, phi, self.cut_threshold) for t, s, phi in zip(trials, starts, phi_refs)]
            sols = [sol for sol, _ in steps]
            gaps = [
                float(w @ (sol.features - phi) / (w @ phi)) if sol.success else float("nan")
                for sol, phi in zip(sols, phi_refs)
            ]
            extra = {"cost_gap": gaps[0] if len(gaps) == 1 else gaps} | steps[0][1]
            history.append(IterationRecord.of(problem, w, sols[0] if len(sols) == 1 else sols, **extra))
            if not all(sol.success for sol in sols):
                status = "forward_failed"
                break
            for k, (sol, phi) in enumerate(zip(sols, phi_refs)):
                if self._is_cut(sol.features, phi):
                    samples[k].append(sol.features)
            if self.stop_without_cut and not any(gap < -self.cut_threshold for gap in gaps):
                status = "converged"  # no cheaper step near any reference: w is consistent with them
                break
            if previous is not None and np.max(np.abs(w - previous)) < self.weight_tol:
                status = "converged"
                break
            previous = w
        if w is None:
            return IOCResult(np.full(problem.n_features, np.nan), f"failed: {status} before the first candidate")
        weights, chosen = self.output(history, w)
        notes["cuts"] = sum(len(s) for s in samples) - notes["random_samples"]
        region = cut_region(self._diffs(samples, phi_refs), problem.n_features, step.lower, problem.seed)
        return IOCResult(weights, status, tuple(history), chosen, notes, uncertainty=_holding(region, weights))

    def _diffs(self, samples: list[list[np.ndarray]], phi_refs: list[np.ndarray]) -> np.ndarray | None:
        rows = [s - (1 - self.cut_threshold) * phi for trial, phi in zip(samples, phi_refs) for s in trial]
        return np.array(rows) if rows else None

    def _samples(self, trials, phi_refs: list[np.ndarray]) -> tuple[list[list[np.ndarray]], dict]:
        samples, notes = [], {"random_samples": 0, "failed_projections": 0}
        for trial, phi in zip(trials, phi_refs):
            own, counts = self._random_samples(trial, phi)
            samples.append(own)
            notes = {k: notes[k] + counts[k] for k in notes}
        return samples, notes

    def _is_cut(self, phi: np.ndarray, phi_ref: np.ndarray) -> bool:
        """Whether a sample differs from the reference by more than the threshold."""
        return bool(np.max(np.abs(phi - phi_ref) / np.maximum(np.abs(phi_ref), 1e-300)) > self.cut_threshold)

    def _random_samples(self, problem: IOCProblem, phi_ref: np.ndarray) -> tuple[list[np.ndarray], dict]:
        """Feature vectors of ``n_random`` projected random perturbations of the observation
        (failed projections and ones indistinguishable from the reference left out). Each
        projection starts warm at the reference, the projected step it perturbs: the same
        projections in fewer iterations than from the perturbed values
        (``docs/notes/2026-12-05-warm-projections.md``; ``benchmarks/projection_starts.py``)."""
        rng = problem.rng(stream=1)
        samples, failed, reference = [], 0, problem.reference()
        for _ in range(self.n_random):
            sol = problem.project(problem.perturb(rng, self.perturbation), start=reference)
            if not sol.success:
                failed += 1
            elif self._is_cut(sol.features, phi_ref):
                samples.append(sol.features)
        return samples, {"random_samples": len(samples), "failed_projections": failed}


def _holding(region: WeightRegion | None, weights: np.ndarray) -> WeightRegion | None:
    """The cut region widened to hold the output (the paper's output, the candidate closest to
    the observation, may lie outside the cone that later cuts leave)."""
    if region is None:
        return None
    w = normalize(weights)
    lower, upper = np.minimum(region.lower, w), np.maximum(region.upper, w)
    if np.array_equal(lower, region.lower) and np.array_equal(upper, region.upper):
        return region
    return replace(
        region, lower=tuple(lower), upper=tuple(upper), method=region.method + ", widened to hold the output"
    )
