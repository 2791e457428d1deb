"""A custom IOC algorithm in 30 lines: random search over weights, scored on the walker.

Run: python examples/custom_algorithm.py
"""

from dataclasses import dataclass

import numpy as np

import ioc_bench
from ioc_bench import IOCAlgorithm, IOCProblem, IOCResult, IterationRecord


@dataclass(frozen=True)
class RandomSearchConfig:
    candidates: int = 6  # forward solves to spend


@ioc_bench.register_algorithm("random-search")
class RandomSearch(IOCAlgorithm):
    """Try random weights; keep the ones whose optimal step is closest to the observation."""

    description = "random weights, keep the one whose optimum looks most like the observation"
    Config = RandomSearchConfig

    def fit(self, problem: IOCProblem) -> IOCResult:
        rng = problem.rng()
        history = []
        for _ in range(self.config.candidates):
            w = rng.uniform(0.05, 1.0, problem.n_features)
            step = problem.optimize(w)  # a counted, timed forward solve under the IOC's model
            history.append(IterationRecord.of(problem, w / np.linalg.norm(w), step))  # its errors
        best = int(np.nanargmin([h.tracking_error for h in history]))
        return IOCResult(np.array(history[best].weights), "max_iterations", tuple(history), best)


if __name__ == "__main__":
    result = ioc_bench.run_case("random-search", weights="penalize-knee", condition="ideal", seed=0)
    print(f"{result.status}: weights {np.round(result.weights, 3)} (true {np.round(result.true_weights, 3)})")
    print(f"weight error {result.weight_error:.3f}, {result.n_solves} forward solves, {result.wall_time:.1f} s")
