"""The leaderboard's intervals: seeds are resampled within weight sets, never across them."""

import numpy as np
import pytest

from ioc_bench.synthetic.statistics import bootstrap_mean_ci, stratified_mean_ci


def test_seeds_that_agree_give_a_point_whatever_the_spread_between_weight_sets():
    strata = [[0.001] * 3, [0.2] * 3, [0.05] * 3, [0.0] * 3]  # 4 weight sets, 3 identical seeds each
    low, high = stratified_mean_ci(strata)
    assert low == pytest.approx(high) == pytest.approx(np.mean(np.concatenate(strata)))
    pooled_low, pooled_high = bootstrap_mean_ci(np.concatenate(strata))  # cases as units: a wide interval
    assert pooled_high - pooled_low > 0.05


def test_seed_spread_gives_an_interval_around_the_mean_and_is_seeded():
    rng = np.random.default_rng(3)
    strata = [list(m + 0.01 * rng.normal(size=3)) for m in (0.1, 0.2, 0.3, 0.4)]
    low, high = stratified_mean_ci(strata)
    mean = np.mean(np.concatenate(strata))
    assert low < mean < high and high - low < 0.03
    assert stratified_mean_ci(strata) == (low, high)


def test_too_few_values_give_no_interval_and_nan_is_ignored():
    assert stratified_mean_ci([[0.1], [0.2]]) is None
    assert stratified_mean_ci([]) is None
    assert stratified_mean_ci([[0.1, float("nan")], [0.2]]) is None
    assert bootstrap_mean_ci([0.3]) is None
