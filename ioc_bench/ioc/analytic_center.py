"""The paper's iterative IOC recast as an analytic-centre cutting-plane method (ACCPM).

Why the printed method stalls on this walker (measured; see docs/ioc.md):

1. Features are 1e-4..1e-6, so ``log(1.5 + w . d)`` is linear in ``w`` to 1e-5: the weight
   step is a linear program whose optimum sits on an edge of the cone of separating
   weights, not inside it, so each new cut removes little.
2. A forward solve under candidate weights, even started from x*, often ends in a local
   optimum that costs *more* than x* under those weights (the knee-lock makes the cost
   landscape rugged). Its features then satisfy the candidate's own constraint, the
   sample adds no cut, and the same weights come back.

This variant fixes both, keeping the paper's structure (samples, weight optimization,
forward solves, iterate):

- the weight step is the analytic centre of the cone of separating weights, in features
  scaled by their observed values, so every cut goes through the middle of what is left;
- the forward step is a proximal solve anchored at x*: minimise ``w.phi(x)/w.phi(x*) +
  lambda * D(x, x*)``. It starts at x*, so it can only come back cheaper under ``w``: if
  ``w`` is not optimal for x* it yields a cut (x* is locally optimal for the true weights,
  so the cut never removes them); if it returns x* itself, ``w`` is consistent with the
  observation. ``lambda`` rises through a ladder until a cut is found;
- it stops when no cut is found at the largest ``lambda`` or the weights stop moving, and
  outputs the last centre;
- when the observation is infeasible for the IOC's model (noise, wrong mass or speed), it
  works around the observation's feasible projection x^ instead (x^ = x* when x* is
  feasible). No weights may make x^ exactly optimal; if the cuts become inconsistent it
  outputs the weights that violate them least (largest smallest margin).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ioc_bench.ioc.algorithm import IOCAlgorithm, IOCResult, IterationRecord
from ioc_bench.ioc.log_barrier import random_samples, record
from ioc_bench.ioc.problem import IOCProblem
from ioc_bench.ioc.registry import register_algorithm
from ioc_bench.ioc.weight_fit import fit_weights
from ioc_bench.trajectory import Trajectory


@dataclass(frozen=True)
class AnalyticCenterConfig:
    """Settings of the cutting-plane variant.

    Attributes:
        n_random: projected random trajectories seeding the cuts, as in the paper (0: none;
            random perturbations cost more under every positive weight, so they cut little).
        perturbation: their noise, as a fraction of each signal's span.
        max_iterations: candidate weights tried at most.
        proximal: ladder of proximal weights ``lambda`` tried until a solve cuts.
        cut_tol: a relative cost decrease below this does not count as a cut.
        weight_tol: stop when no weight (unit norm) moves more than this.
    """

    n_random: int = 0
    perturbation: float = 0.05
    max_iterations: int = 40
    proximal: tuple[float, ...] = (30.0, 300.0)
    cut_tol: float = 1e-7
    weight_tol: float = 2e-4

    def __post_init__(self) -> None:
        if self.n_random < 0 or self.max_iterations < 1 or not self.proximal:
            raise ValueError("n_random >= 0, max_iterations >= 1 and a non-empty proximal ladder are required")
        if any(p <= 0 for p in self.proximal) or self.cut_tol < 0 or self.weight_tol < 0:
            raise ValueError("proximal weights must be > 0, cut_tol and weight_tol >= 0")


@register_algorithm("analytic-center")
class AnalyticCenter(IOCAlgorithm):
    """Log-barrier IOC as an analytic-centre cutting-plane method with proximal cuts."""

    description = "log-barrier IOC as an analytic-centre cutting-plane method (scaled features, proximal cuts)"
    Config = AnalyticCenterConfig

    def fit(self, problem: IOCProblem) -> IOCResult:
        cfg: AnalyticCenterConfig = self.config
        anchor = self._anchor(problem)
        if anchor is None:
            return IOCResult(np.full(problem.n_features, np.nan), "failed: the observation could not be projected")
        phi_star = problem.features_of(anchor)
        scale = np.maximum(phi_star, 1e-3 * phi_star.max())  # feature j is measured in units of phi^_j
        samples, failed = random_samples(problem, cfg.n_random, cfg.perturbation)
        cuts = [(phi - phi_star) / scale for phi in samples]
        history: list[IterationRecord] = []
        status, previous, w, previous_scaled = "max_iterations", None, None, None
        for _ in range(cfg.max_iterations):
            fit = fit_weights(np.array(cuts), "center", lower=0.0, upper=1.0) if cuts else None
            if fit is not None and not fit.success:
                status = "infeasible"
                least = fit_weights(np.array(cuts), "maxmin", lower=0.0, upper=1.0, start=previous_scaled)
                w = _unit(least.weights / scale) if least.success else w
                break
            scaled = fit.weights if fit else np.full(problem.n_features, 1.0)
            previous_scaled = scaled
            w = _unit(scaled / scale)
            sol, lam = self._cut(problem, w, anchor, phi_star, cfg)
            history.append(record(problem, w, sol, phi_star, proximal=lam))
            if not history[-1].cost_gap < -cfg.cut_tol:
                status = "converged"  # no cheaper step near x*: w is consistent with it
                break
            cuts.append((sol.features - phi_star) / scale)
            if previous is not None and np.max(np.abs(w - previous)) < cfg.weight_tol:
                status = "converged"
                break
            previous = w
        if w is None:
            return IOCResult(np.full(problem.n_features, np.nan), "failed: no candidate weights")
        chosen = len(history) - 1 if history and status != "infeasible" else None
        return IOCResult(
            weights=w,
            status=status,
            history=tuple(history),
            chosen_iteration=chosen,
            notes={"cuts": len(cuts), "random_samples": len(samples), "failed_projections": failed},
        )

    @staticmethod
    def _anchor(problem: IOCProblem) -> Trajectory | None:
        """The observation if the IOC's model can produce it, else its feasible projection."""
        if problem.is_feasible(problem.observed):
            return problem.observed
        projected = problem.project(problem.observed)
        return projected.trajectory if projected.success else None

    @staticmethod
    def _cut(problem: IOCProblem, w: np.ndarray, anchor: Trajectory, phi_star: np.ndarray, cfg: AnalyticCenterConfig):
        """Proximal solves from the anchor along the ladder until one is cheaper under w."""
        for lam in cfg.proximal:
            sol = problem.optimize(w, start=anchor, proximal=lam, anchor=anchor)
            if sol.success and w @ (sol.features - phi_star) < -cfg.cut_tol * (w @ phi_star):
                return sol, lam
        return sol, lam


def _unit(w: np.ndarray) -> np.ndarray:
    return w / np.linalg.norm(w)
