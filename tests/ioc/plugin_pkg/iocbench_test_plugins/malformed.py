"""A plugin whose answer breaks the contract in a way its config chooses (after real solves)."""

from dataclasses import dataclass

import numpy as np

from ioc_bench import IOCAlgorithm, IOCResult, IterationRecord, WeightRegion

KINDS = (
    "fields-in-wrong-order",
    "dict-record",
    "string-error",
    "string-weights",
    "record-weights-wrong-size",
    "chosen-out-of-range",
    "notes-not-json",
    "status-not-text",
    "region-inverted",
    "region-wrong-size",
    "nan-weights",
    "not-a-result",
)


@dataclass(frozen=True)
class MalformedConfig:
    kind: str = "fields-in-wrong-order"


class Malformed(IOCAlgorithm):
    description = "returns a malformed answer (for the contract tests)"
    Config = MalformedConfig

    def fit(self, problem):
        w = np.ones(problem.n_features) / np.sqrt(problem.n_features)
        sol = problem.optimize(w)  # a real solve: the failed record must count it
        good = IterationRecord.of(problem, w, sol)
        kind = self.config.kind
        history, weights, chosen, notes, status, region = (good,), w, 0, {}, "converged", None
        if kind == "fields-in-wrong-order":
            history = (IterationRecord(tuple(w), sol.status, 0.1, 0.2),)
        elif kind == "dict-record":
            history = (good.to_dict(),)
        elif kind == "string-error":
            history = (IterationRecord(tuple(w), tracking_error="0.1", trajectory_error=0.2),)
        elif kind == "string-weights":
            weights = np.array(["0.5", "0.5", "0.7"][: problem.n_features])
        elif kind == "record-weights-wrong-size":
            history = (IterationRecord((1.0,), tracking_error=0.1, trajectory_error=0.2),)
        elif kind == "chosen-out-of-range":
            chosen = 5
        elif kind == "notes-not-json":
            notes = {"solution": sol}
        elif kind == "status-not-text":
            status = 3
        elif kind == "region-inverted":
            region = WeightRegion(lower=tuple(w + 0.1), upper=tuple(w - 0.1))
        elif kind == "region-wrong-size":
            region = WeightRegion(lower=(0.0,), upper=(1.0,))
        elif kind == "nan-weights":
            weights = np.full(problem.n_features, np.nan)
        elif kind == "not-a-result":
            return {"weights": w}
        return IOCResult(weights, status, history, chosen, notes, uncertainty=region)
