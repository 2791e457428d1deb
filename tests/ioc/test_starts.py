"""The further starts of the fitting methods: unit-norm, floored, one dominant feature each."""

from __future__ import annotations

import numpy as np

from ioc_bench.ioc.starts import DOMINANT, MORE_STARTS, further_starts


def test_further_starts_floor_the_inverse_kkt_weights_and_give_each_feature_a_turn():
    starts = further_starts(np.array([0.0, 2.0, 1e-9]))
    assert len(starts) == 4 and all(np.isclose(np.linalg.norm(s), 1.0) for s in starts)
    floored = starts[0] / starts[0].max()
    assert np.allclose(floored, [MORE_STARTS, 1.0, MORE_STARTS])
    for i, s in enumerate(starts[1:]):
        assert np.argmax(s) == i and np.isclose(s[i] / np.delete(s, i).max(), DOMINANT)
