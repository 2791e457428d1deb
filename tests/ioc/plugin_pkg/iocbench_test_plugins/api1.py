"""A coordinate-search plugin written to API 1 (the README of the first release).

API 1's record was ``IterationRecord(weights, trajectory_error, solve_status, cost_gap,
extra)``: its second positional argument is the paper's trajectory error.
"""

from dataclasses import dataclass

import numpy as np

from ioc_bench import IOCAlgorithm, IOCResult, IterationRecord


@dataclass(frozen=True)
class CoordinateSearchConfig:
    step: float = 0.2


class CoordinateSearch(IOCAlgorithm):
    description = "coordinate search on the trajectory error (written to API 1)"
    Config = CoordinateSearchConfig

    def fit(self, problem):
        w = np.ones(problem.n_features) / np.sqrt(problem.n_features)
        history = []
        for trial in (w, w * np.exp(self.config.step * np.eye(problem.n_features)[1])):
            trial = trial / np.linalg.norm(trial)
            sol = problem.optimize(trial)
            error = problem.trajectory_error(sol.trajectory) if sol.success else float("nan")
            history.append(IterationRecord(tuple(trial), error, sol.status))  # API 1, positional
        best = int(np.nanargmin([h.trajectory_error for h in history]))
        return IOCResult(np.array(history[best].weights), "converged", tuple(history), best)
