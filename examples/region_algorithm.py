"""A plugin that says how sure it is: inverse KKT with a bootstrap region for its weights.

The estimate is the built-in inverse-KKT fit at the feasible reference. Its region comes from
a parametric bootstrap over the observation: the observation is perturbed with noise of the
level estimated from the observation itself (``problem.noise_level``), projected, and
refitted, ``resamples`` times; each weight's interval is the 2.5-97.5 % range of the
resampled weights (``WeightRegion``, API 3; the leaderboard measures whether it covers the
truth). Run: ``python examples/region_algorithm.py``.
"""

from dataclasses import dataclass

import numpy as np

import ioc_bench
from ioc_bench import IOCAlgorithm, IOCProblem, IOCResult, WeightRegion
from ioc_bench.ioc.inverse_kkt import InverseKKTConfig, fit_kkt


def unit(w: np.ndarray) -> np.ndarray:
    """The weights at unit norm: a region is stated for the unit-norm weights."""
    return np.asarray(w, dtype=float) / np.linalg.norm(w)


@dataclass(frozen=True)
class BootstrapConfig:
    resamples: int = 20  # projections of perturbed observations (each a counted forward solve)
    floor: float = 0.01  # noise level used when the observation looks exact (fraction of span)


@ioc_bench.register_algorithm("bootstrap-kkt")
class BootstrapKKT(IOCAlgorithm):
    """Inverse KKT at the reference, with a parametric-bootstrap region."""

    description = "inverse KKT with a parametric-bootstrap 95 % region (an example plugin)"
    family = "inverse-kkt"
    Config = BootstrapConfig

    def fit(self, problem: IOCProblem) -> IOCResult:
        view, cfg = problem.forward, InverseKKTConfig()
        estimate = unit(fit_kkt(view, view.vector(problem.reference().trajectory), cfg).weights)
        rng, noise = problem.rng(stream=3), max(problem.noise_level, self.config.floor)
        resampled = []
        for _ in range(self.config.resamples):
            projected = problem.project(problem.perturb(rng, noise))
            if projected.success:
                resampled.append(unit(fit_kkt(view, view.vector(projected.trajectory), cfg).weights))
        if len(resampled) < 2:
            return IOCResult(estimate, "converged", notes={"resampled": len(resampled)})
        lower, upper = np.percentile(resampled, [2.5, 97.5], axis=0)
        region = WeightRegion(
            tuple(np.minimum(lower, estimate)),
            tuple(np.maximum(upper, estimate)),
            0.95,
            method=f"parametric bootstrap, {len(resampled)} resamples at noise {noise:.3g}",
        )
        return IOCResult(estimate, "converged", notes={"resampled": len(resampled)}, uncertainty=region)


if __name__ == "__main__":
    result = ioc_bench.run_case("bootstrap-kkt", weights="penalize-knee", condition="noise", seed=0)
    print(f"weights {np.round(result.weights, 3)} (true {np.round(result.true_weights, 3)})")
    print(
        f"region {np.round(result.uncertainty['lower'], 3)} .. {np.round(result.uncertainty['upper'], 3)}, "
        f"holds the truth: {result.covered}"
    )
