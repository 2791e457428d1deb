"""A plugin written to API 3: keyword records and a region for its weights."""

import numpy as np

from ioc_bench import IOCAlgorithm, IOCResult, IterationRecord, WeightRegion


class WithRegion(IOCAlgorithm):
    description = "one candidate with a (wide) region (written to API 3)"

    def fit(self, problem):
        w = np.ones(problem.n_features) / np.sqrt(problem.n_features)
        sol = problem.optimize(w)
        record = IterationRecord.of(problem, w, sol)
        region = WeightRegion(lower=tuple(np.zeros_like(w)), upper=tuple(np.ones_like(w)), method="everything")
        return IOCResult(w, "converged", (record,), 0, uncertainty=region)
