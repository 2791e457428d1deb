"""A gradient-based IOC plugin written from the public API only (docs/plugin_api.md, docs/differentiable.md).

Gradient descent on the tracking error of the weights' optimum, on the unit sphere of
weights: the gradient comes from the forward problem's KKT sensitivity
(``problem.forward.sensitivity``); the step grows after a success and shrinks after a miss.
Run: ``python examples/gradient_algorithm.py``.
"""

from dataclasses import dataclass

import numpy as np

import ioc_bench
from ioc_bench import IOCAlgorithm, IOCProblem, IOCResult, IterationRecord


@dataclass(frozen=True)
class GradientConfig:
    iterations: int = 12  # gradient steps
    step: float = 0.3  # first step along the sphere of unit weights (radians, about)


@ioc_bench.register_algorithm("tracking-gradient")
class TrackingGradient(IOCAlgorithm):
    """Descend the tracking error of x*(w) with implicit gradients."""

    description = "projected gradient descent on the optimum's tracking error (KKT sensitivity)"
    family = "bilevel"
    Config = GradientConfig

    def fit(self, problem: IOCProblem) -> IOCResult:
        view, start = problem.forward, problem.reference()  # the projected observation
        w = np.ones(problem.n_features) / np.sqrt(problem.n_features)
        history, error, step = [], np.inf, self.config.step
        for _ in range(self.config.iterations):
            sol = problem.optimize(w, start=start)  # warm-started at the projected observation
            history.append(IterationRecord.of(problem, w, sol))
            error, grad_x = view.tracking_error(view.vector(sol.trajectory))
            grad = grad_x @ view.sensitivity(sol)  # (F,) d error / d weights, through the KKT system
            tangent = grad - w * (w @ grad)  # along the sphere of unit weights
            while step > 1e-4:
                trial = np.maximum(w - step * tangent / np.linalg.norm(tangent), 1e-9)
                trial /= np.linalg.norm(trial)
                if view.tracking_error(view.vector(problem.optimize(trial, start=start).trajectory))[0] < error:
                    w, step = trial, step * 1.5
                    break
                step /= 2
        return IOCResult(w, "max_iterations", tuple(history), len(history) - 1, {"tracking_error": error})


if __name__ == "__main__":
    result = ioc_bench.run_case("tracking-gradient", weights="penalize-knee", condition="ideal", seed=0)
    print(f"weights {np.round(result.weights, 3)} (true {np.round(result.true_weights, 3)})")
    print(f"weight error {result.weight_error:.4f}, {result.n_solves} forward solves, {result.wall_time:.1f} s")
