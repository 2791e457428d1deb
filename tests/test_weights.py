from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

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


def test_six_features_say_three_or_six():
    from ioc_bench.features import ALL_FEATURES

    with pytest.raises(ValueError, match=r"expected 3 weights \(hip, knee, dtau\) or 6"):
        parse_weights("1,2", ALL_FEATURES)


_number_text = st.one_of(
    st.floats(allow_nan=True, allow_infinity=True).map(repr),
    st.integers(-5, 10**6).map(str),
    st.sampled_from(["", " ", "x", "1e999", "-0", "1_0", "0x1", "nan", "inf", "+1", "1e-320"]),
)
_specs = st.one_of(
    st.text(max_size=20),
    st.lists(_number_text, min_size=0, max_size=7).map(",".join),
    st.sampled_from([*WEIGHT_SETS, "Nominal", "nominal ", "penalize-"]),
    st.lists(st.floats() | st.integers() | st.booleans() | st.none() | st.text(max_size=3), max_size=7),
    st.dictionaries(
        st.sampled_from(["hip", "knee", "dtau", "torso", "x"]),
        st.floats() | st.integers() | st.none() | st.text(max_size=3) | st.lists(st.floats(), max_size=2),
        max_size=4,
    ),
    st.lists(st.floats(min_value=1e150) | st.floats(max_value=1e-300, min_value=0), min_size=3, max_size=3),
    st.none() | st.booleans() | st.integers() | st.floats(),
)


@settings(max_examples=500)
@given(spec=_specs)
def test_property_parse_weights_gives_unit_weights_or_a_value_error(spec):
    """Any input: three finite non-negative weights of unit norm, or ``ValueError`` (never another type)."""
    try:
        w = parse_weights(spec)
    except ValueError as exc:
        assert "\n" not in str(exc)
        return
    assert w.shape == (3,) and np.all(np.isfinite(w)) and np.all(w >= 0)
    assert np.linalg.norm(w) == pytest.approx(1.0, abs=1e-12)


def test_weight_sets_drawn_from_the_simplex_are_seeded_distinct_and_parse() -> None:
    from ioc_bench.weights import parse_weights, simplex_weight_sets

    drawn = simplex_weight_sets(12, seed=2026)
    assert drawn == simplex_weight_sets(12, seed=2026) != simplex_weight_sets(12, seed=2027)
    assert len(set(drawn)) == 12
    values = np.array([[float(x) for x in w.split(",")] for w in drawn])
    assert np.all(values >= 0) and np.allclose(values.sum(axis=1), 1.0, atol=2e-3)  # on the simplex, 3 decimals
    assert all(np.isclose(np.linalg.norm(parse_weights(w)), 1.0) for w in drawn)
