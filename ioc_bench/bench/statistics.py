"""Interval estimates for the leaderboard, over independent cases.

Every case of a cell is an independent experiment: its seed re-solves the demonstration
from its own multi-start, draws its own observation noise and seeds the algorithm's
randomness. So the cases themselves are the resampling units (a percentile bootstrap of
the mean over them), and the interval covers what a new experiment with these weight
sets would give.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

#: Bootstrap resamples.
RESAMPLES = 9999


def bootstrap_mean_ci(values: Sequence[float], seed: int = 0) -> tuple[float, float] | None:
    """95 % percentile-bootstrap interval of the mean of the finite ``values`` (None if fewer
    than two; a point if all are equal)."""
    from scipy.stats import bootstrap

    arr = np.asarray([v for v in values if np.isfinite(v)], dtype=float)
    if arr.size < 2:
        return None
    if np.ptp(arr) == 0:
        return float(arr.mean()), float(arr.mean())
    res = bootstrap(
        (arr,),
        np.mean,
        confidence_level=0.95,
        n_resamples=RESAMPLES,
        method="percentile",
        rng=np.random.default_rng(seed),
    )
    return float(res.confidence_interval.low), float(res.confidence_interval.high)
