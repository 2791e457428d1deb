"""Interval estimates for the leaderboard.

A leaderboard cell is a fixed design: every weight set, each with several seeds. A seed is
what a new experiment would change: it re-solves the demonstration from its own
multi-start, draws its own observation noise and seeds the algorithm's randomness. The
weight sets are chosen, not sampled. So the cell's interval resamples seeds *within* each
weight set (a stratified percentile bootstrap of the mean, :func:`stratified_mean_ci`) and
covers what repeating the study with these weight sets would give. Measured: the
15-start demonstrations of different seeds agree to 1e-5 in their angles (the optimum has one basin;
`docs/gait_regime.md`), so without noise a deterministic algorithm returns one value per
weight set and its interval is a point. That is the honest answer, not a lack of data.

:func:`bootstrap_mean_ci` (cases as the units) serves the robustness curves, whose
points have one seed per weight set: their interval is over the weight sets; and
``ioc-bench compare`` (:mod:`ioc_bench.synthetic.compare`), whose units are the paired
differences of two runs' cases.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

#: Bootstrap resamples.
RESAMPLES = 9999
#: Minimum seeds per weight set for a bootstrap confidence interval.
MIN_SEEDS_FOR_CI = 3


def finite_mean(values: Sequence[float]) -> float:
    """The mean of the finite ``values`` (NaN if there is none)."""
    arr = np.asarray([v for v in values if np.isfinite(v)], dtype=float)
    return float(arr.mean()) if arr.size else float("nan")


def bootstrap_mean_ci(values: Sequence[float], seed: int = 0, level: float = 0.95) -> tuple[float, float] | None:
    """Percentile-bootstrap interval (95 % unless ``level`` says otherwise) of the mean of the
    finite ``values`` (None if fewer than two; a point if all are equal)."""
    from scipy.stats import bootstrap

    arr = np.asarray([v for v in values if np.isfinite(v)], dtype=float)
    if arr.size < 2:
        return None
    if np.ptp(arr) == 0:
        return float(arr.mean()), float(arr.mean())
    res = bootstrap(
        (arr,),
        np.mean,
        confidence_level=level,
        n_resamples=RESAMPLES,
        method="percentile",
        rng=np.random.default_rng(seed),
    )
    return float(res.confidence_interval.low), float(res.confidence_interval.high)


def stratified_mean_ci(
    strata: Sequence[Sequence[float]],
    resamples: int = RESAMPLES,
    seed: int = 0,
    shares: Sequence[float] | None = None,
) -> tuple[float, float] | None:
    """95 % percentile interval of the mean over all values, resampling each stratum's
    finite values with replacement within the stratum (None if no stratum has two values).

    ``shares`` (one per stratum, summing to 1) make the statistic the weighted mean of the
    strata's means instead, e.g. every condition counted equally however many cases it has;
    a stratum left without finite values drops out and the others' shares are rescaled."""
    given = [1.0] * len(strata) if shares is None else list(shares)
    if len(given) != len(strata):
        raise ValueError(f"shares has {len(given)} entries for {len(strata)} strata")
    kept = [
        (np.asarray(arr, dtype=float), share)
        for arr, share in (([v for v in g if np.isfinite(v)], s) for g, s in zip(strata, given))
        if arr
    ]
    if not kept or max(g.size for g, _ in kept) < 2:
        return None
    groups = [g for g, _ in kept]
    if shares is None:  # the plain mean: each value counts once
        weights = np.array([g.size for g in groups], dtype=float)
    else:
        weights = np.array([share for _, share in kept], dtype=float)
    weights /= weights.sum()
    rng = np.random.default_rng(seed)
    means = sum(w * rng.choice(g, size=(resamples, g.size), replace=True).mean(axis=1) for g, w in zip(groups, weights))
    low, high = np.percentile(means, [2.5, 97.5])
    return float(low), float(high)
