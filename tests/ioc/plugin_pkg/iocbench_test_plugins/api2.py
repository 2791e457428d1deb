"""A plugin written to API 2: ``IterationRecord(weights, tracking_error, trajectory_error,
solve_status, extra)`` by position."""

import numpy as np

from ioc_bench import IOCAlgorithm, IOCResult, IterationRecord


class TwoCandidates(IOCAlgorithm):
    description = "the better of two candidates (written to API 2)"
    family = "other"

    def fit(self, problem):
        history = []
        for raw in (np.ones(problem.n_features), np.arange(1.0, problem.n_features + 1)):
            w = raw / np.linalg.norm(raw)
            sol = problem.optimize(w)
            track = problem.tracking_error(sol.trajectory)
            traj = problem.trajectory_error(sol.trajectory)
            history.append(IterationRecord(tuple(w), track, traj, sol.status, {"candidate": len(history)}))
        best = int(np.argmin([h.tracking_error for h in history]))
        return IOCResult(np.array(history[best].weights), "converged", tuple(history), best, {"note": "api 2"})
