"""The paper's IOC method (Rebula et al., section II.D; SPEC section 3), as printed.

1. Draw N trajectories around the observed one with Gaussian noise and project each to
   the feasible set: the suboptimal set X-.
2. Find weights maximising ``sum log(1.5 + w . (phi(x-) - phi(x*)))`` subject to every
   x- costing more than x*, ``|w| = 1`` and ``0.001 < w_i < 0.999``.
3. Optimise a step for the candidate weights (from x*), add it to X-, repeat from 2; stop
   after ``max_iterations``, when the weights stop changing, or when step 2 is infeasible.
4. Output the candidate whose step was closest to the observation.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ioc_bench.ioc.algorithm import IOCAlgorithm, IOCResult, IterationRecord
from ioc_bench.ioc.problem import IOCProblem, OracleSolution
from ioc_bench.ioc.registry import register_algorithm
from ioc_bench.ioc.weight_fit import fit_weights


@dataclass(frozen=True)
class LogBarrierConfig:
    """Settings of the paper's method.

    Attributes:
        n_random: N, projected random trajectories that seed X- (the paper does not say;
            10 keeps a case under a minute here).
        perturbation: noise of the random trajectories, as a fraction of each signal's span.
        max_iterations: the paper's 25.
        weight_tol: stop when no weight changes by more than this between iterations.
        offset: the 1.5 inside the log.
        lower, upper: the weight bounds 0.001 and 0.999.
    """

    n_random: int = 10
    perturbation: float = 0.05
    max_iterations: int = 25
    weight_tol: float = 1e-4
    offset: float = 1.5
    lower: float = 0.001
    upper: float = 0.999

    def __post_init__(self) -> None:
        if self.n_random < 1 or self.max_iterations < 1:
            raise ValueError("n_random and max_iterations must be >= 1")
        if not (self.perturbation > 0 and self.weight_tol >= 0 and 0 <= self.lower < self.upper <= 1):
            raise ValueError("perturbation must be > 0, weight_tol >= 0 and 0 <= lower < upper <= 1")


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


def record(problem: IOCProblem, w: np.ndarray, sol: OracleSolution, phi_star: np.ndarray, **extra) -> IterationRecord:
    """The history entry of one candidate and its forward solve."""
    gap = float(w @ (sol.features - phi_star) / (w @ phi_star)) if sol.success else float("nan")
    return IterationRecord(
        weights=tuple(float(x) for x in w),
        trajectory_error=problem.trajectory_error(sol.trajectory) if sol.success else float("nan"),
        solve_status=sol.status,
        cost_gap=gap,
        extra=extra,
    )


@register_algorithm("log-barrier")
class LogBarrier(IOCAlgorithm):
    """Iterative log-barrier IOC exactly as the paper prints it."""

    description = "the paper's iterative log-barrier IOC (Rebula et al. 2019), as printed"
    Config = LogBarrierConfig

    def fit(self, problem: IOCProblem) -> IOCResult:
        cfg: LogBarrierConfig = self.config
        phi_star = problem.features_of(problem.observed)
        samples, failed = random_samples(problem, cfg.n_random, cfg.perturbation)
        n_random = len(samples)
        history: list[IterationRecord] = []
        status, previous = "max_iterations", None
        for _ in range(cfg.max_iterations):
            fit = fit_weights(np.array(samples) - phi_star, "paper", cfg.offset, cfg.lower, cfg.upper, previous)
            if not fit.success:
                status = "infeasible"
                break
            sol = problem.optimize(fit.weights, start=problem.observed)
            history.append(record(problem, fit.weights, sol, phi_star, min_margin=fit.min_margin))
            if sol.success:
                samples.append(sol.features)
            if previous is not None and np.max(np.abs(fit.weights - previous)) < cfg.weight_tol:
                status = "converged"
                break
            previous = fit.weights
        if not history:
            return IOCResult(np.full(problem.n_features, np.nan), f"failed: {status} before the first candidate")
        chosen = int(np.nanargmin([h.trajectory_error for h in history])) if _any_finite(history) else len(history) - 1
        return IOCResult(
            weights=np.array(history[chosen].weights),
            status=status,
            history=tuple(history),
            chosen_iteration=chosen,
            notes={"random_samples": n_random, "failed_projections": failed},
        )


def _any_finite(history: list[IterationRecord]) -> bool:
    return any(np.isfinite(h.trajectory_error) for h in history)
