from __future__ import annotations

import numpy as np
import pytest

from ioc_bench.weights import WEIGHT_SETS, parse_weights


def test_named_sets_are_unit_norm_in_hip_knee_dtau_order():
    assert list(WEIGHT_SETS) == ["nominal", "penalize-hip", "penalize-knee", "penalize-dtau"]
    w = parse_weights("penalize-knee")
    assert np.linalg.norm(w) == pytest.approx(1.0) and np.argmax(w) == 1


@pytest.mark.parametrize(
    ("spec", "message"),
    [
        ("bogus", "unknown weight set"),
        ("1,x,1", "cannot read"),
        ("1,2", "expected 3 weights"),
        ("1,-1,1", "non-negative"),
        ("nan,1,1", "finite"),
        ("0,0,0", "all be zero"),
        ({"nope": 1.0}, "unknown feature"),
    ],
)
def test_bad_weights_are_one_line_errors(spec, message):
    with pytest.raises(ValueError, match=message):
        parse_weights(spec)


def test_numbers_and_mappings():
    assert parse_weights("1,10,1") == pytest.approx(parse_weights("penalize-knee"))
    assert parse_weights({"knee": 1.0}) == pytest.approx([0, 1, 0])
