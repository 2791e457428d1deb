"""A plugin written to API 4: a region and its own test of whether the model fits."""

import numpy as np

from ioc_bench import IOCAlgorithm, IOCResult, IterationRecord, ModelFit, WeightRegion


class WithModelFit(IOCAlgorithm):
    description = "one candidate with a region and a misfit test that always rejects (written to API 4)"

    def fit(self, problem):
        w = np.ones(problem.n_features) / np.sqrt(problem.n_features)
        sol = problem.optimize(w)
        record = IterationRecord.of(problem, w, sol)
        region = WeightRegion(lower=tuple(np.zeros_like(w)), upper=tuple(np.ones_like(w)), method="everything")
        fit = ModelFit(
            rejected=True,
            statistic=record.tracking_error / max(problem.noise_level, 1e-6) ** 2,
            threshold=0.0,
            noise_level=problem.noise_level,
            tracking_error=record.tracking_error,
            method="rejects every model",
        )
        return IOCResult(w, "converged", (record,), 0, uncertainty=region, model_fit=fit)
