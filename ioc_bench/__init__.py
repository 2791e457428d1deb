"""ioc-bench: a benchmark for inverse optimal control of bipedal walking.

The forward problem (optimal gaits of a 5-segment planar walker) after Rebula, Schaal,
Finley & Righetti, "A Robustness Analysis of Inverse Optimal Control of Bipedal Walking".

What long calls do (a run's cases, demonstrations solved or read from the cache, workers
that died) is reported through the ``ioc_bench`` logger and its children, which have no
handler but a :class:`logging.NullHandler`: the application decides where it goes
(docs/python_api.md, *Logging*).
"""

from __future__ import annotations

import importlib
import logging
from typing import Any

from ioc_bench._version import __version__

logging.getLogger(__name__).addHandler(logging.NullHandler())

#: Where each public name lives; imported on first use, so ``import ioc_bench`` (and the
#: command line's start, when Ctrl-C must already be honoured) does not load CasADi.
_PUBLIC = {
    "CaseResult": "ioc_bench.synthetic.case",
    "run_case": "ioc_bench.synthetic.case",
    "CONDITIONS": "ioc_bench.synthetic.conditions",
    "Condition": "ioc_bench.synthetic.conditions",
    "Demonstration": "ioc_bench.demo",
    "DemonstrationFileError": "ioc_bench.demo",
    "ALL_FEATURES": "ioc_bench.features",
    "COST_FEATURES": "ioc_bench.features",
    "DISTRACTORS": "ioc_bench.features",
    "FEATURES": "ioc_bench.features",
    "API_VERSION": "ioc_bench.ioc",
    "IOCAlgorithm": "ioc_bench.ioc",
    "IOCProblem": "ioc_bench.ioc",
    "IOCResult": "ioc_bench.ioc",
    "IterationRecord": "ioc_bench.ioc",
    "ModelFit": "ioc_bench.ioc",
    "OracleSolution": "ioc_bench.ioc",
    "WeightRegion": "ioc_bench.ioc",
    "algorithms": "ioc_bench.ioc",
    "make_algorithm": "ioc_bench.ioc",
    "register_algorithm": "ioc_bench.ioc",
    "SegmentParams": "ioc_bench.model.params",
    "WalkerParams": "ioc_bench.model.params",
    "optimize_gait": "ioc_bench.optimize",
    "Task": "ioc_bench.task",
    "WEIGHT_SETS": "ioc_bench.weights",
    "parse_weights": "ioc_bench.weights",
}


def __getattr__(name: str) -> Any:
    if name not in _PUBLIC:
        raise AttributeError(f"module 'ioc_bench' has no attribute {name!r}")
    value = getattr(importlib.import_module(_PUBLIC[name]), name)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted([*globals(), *_PUBLIC])


__all__ = [
    "ALL_FEATURES",
    "API_VERSION",
    "CONDITIONS",
    "COST_FEATURES",
    "DISTRACTORS",
    "FEATURES",
    "WEIGHT_SETS",
    "CaseResult",
    "Condition",
    "Demonstration",
    "DemonstrationFileError",
    "IOCAlgorithm",
    "IOCProblem",
    "IOCResult",
    "IterationRecord",
    "ModelFit",
    "OracleSolution",
    "SegmentParams",
    "Task",
    "WalkerParams",
    "WeightRegion",
    "__version__",
    "algorithms",
    "make_algorithm",
    "optimize_gait",
    "parse_weights",
    "register_algorithm",
    "run_case",
]
