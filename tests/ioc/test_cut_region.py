"""The region a cutting-plane method's cuts leave."""

import numpy as np

from ioc_bench.ioc.cut_region import cut_region


def test_no_cuts_leave_every_weight():
    region = cut_region(None, 3)
    assert np.allclose(region.lower, 0, atol=1e-6) and np.allclose(region.upper, 1, atol=1e-6)


def test_cuts_shrink_the_region_around_the_weights_they_keep():
    truth = np.array([0.1, 0.99, 0.1]) / np.linalg.norm([0.1, 0.99, 0.1])
    rng = np.random.default_rng(0)
    diffs = []
    while len(diffs) < 30:  # samples costlier than the reference under the truth
        d = rng.normal(size=3)
        if d @ truth > 0:
            diffs.append(d)
    region = cut_region(np.array(diffs), 3)
    assert region.contains(truth)
    assert region.width < 0.3 and "relaxed" not in region.method
    wrong = np.array([0.9, 0.1, 0.42]) / np.linalg.norm([0.9, 0.1, 0.42])
    assert not region.contains(wrong)


def test_inconsistent_cuts_give_a_relaxed_region_that_says_so():
    diffs = np.array([[1.0, -1.0, 0.0], [-1.0, 1.0, 0.0], [0.0, 0.0, -1.0], [-1.0, -1.0, -0.5]])
    region = cut_region(diffs, 3)
    assert region is not None and "relaxed" in region.method
    assert all(lo <= hi for lo, hi in zip(region.lower, region.upper))


def test_the_same_cuts_give_the_same_region():
    diffs = np.random.default_rng(1).normal(size=(10, 3)) + np.array([0.5, 0.5, 0.5])
    assert cut_region(diffs, 3, seed=4) == cut_region(diffs, 3, seed=4)
