"""The fit step every track runs: an algorithm on a problem, its answer checked at the boundary.

Synthetic and human cases alike build their algorithm once (from the registry), hand it the
problem, time it, count its forward solves, and check what it returned against the plugin contract
(:mod:`ioc_bench.ioc.contract`). Whatever goes wrong (the algorithm raises, returns
something the contract refuses, or is given several trials it cannot take) becomes a
:class:`Fit` with a reason, never an exception: a failed fit is a recorded result.
"""

from __future__ import annotations

import time
import traceback
from dataclasses import dataclass
from typing import Any

from ioc_bench.ioc.algorithm import IOCAlgorithm, IOCResult
from ioc_bench.ioc.contract import contract_breach
from ioc_bench.ioc.oracle import OracleStats
from ioc_bench.ioc.problem import REUSED_REFERENCE, IOCProblem, MultiTrialProblem


@dataclass(frozen=True, eq=False)
class Fit:
    """What one fit gave: the algorithm's checked answer, or why there is none.

    Attributes:
        result: the answer, if the contract accepted it (None otherwise).
        reason: why the fit failed ("" if it did not).
        wall_time: seconds the algorithm ran, plus those of stored references it reused
            (computed by an earlier case), so a case's time does not depend on what ran before.
        stats: the problem's oracle counts when the algorithm stopped (before any scoring).
        config: the algorithm's effective config.
    """

    result: IOCResult | None
    reason: str
    wall_time: float
    stats: OracleStats
    config: dict[str, Any]

    @property
    def failed(self) -> bool:
        return self.result is None

    @property
    def n_solves(self) -> int:
        return self.stats.forward_solves


def fit(algo: IOCAlgorithm, problem: IOCProblem | MultiTrialProblem) -> Fit:
    """Run ``algo`` (the case's algorithm, built once by the case from the registry) on
    ``problem``; its own faults are a failed :class:`Fit`, never an exception."""
    settings = algo.config_dict()
    if len(problem.trials) > 1 and not algo.multi_trial:
        reason = f"{algo.name} does not handle several trials (its multi_trial is False)"
        return Fit(None, reason, 0.0, problem.stats.copy(), settings)
    t0 = time.perf_counter()
    try:
        result = algo.fit(problem)
    except Exception as exc:  # the algorithm's fault is a recorded result, not a crash
        last = traceback.extract_tb(exc.__traceback__)[-1]
        reason = f"{type(exc).__name__}: {exc} (at {last.filename}:{last.lineno})"
        return Fit(None, reason, _elapsed(problem, t0), problem.stats.copy(), settings)
    wall = _elapsed(problem, t0)
    reason = contract_breach(result, problem.n_features)
    return Fit(None if reason else result, reason, wall, problem.stats.copy(), settings)


def _elapsed(problem: IOCProblem | MultiTrialProblem, t0: float) -> float:
    return time.perf_counter() - t0 + problem.stats.seconds[REUSED_REFERENCE]
