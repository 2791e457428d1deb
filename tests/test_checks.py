"""Checks of values from outside: seeds, counts, and JSON values against type annotations."""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import pytest

from ioc_bench.checks import TypeMismatch, check_count, check_seed, coerce


@pytest.mark.parametrize("seed", [-1, 1.0, "0", True, None])
def test_bad_seeds(seed):
    with pytest.raises(ValueError, match="seed must be a non-negative integer"):
        check_seed(seed)


def test_seeds_and_counts():
    assert check_seed(np.int64(3)) == 3 and check_count(2, "starts") == 2 and check_count(None, "w", True) is None
    with pytest.raises(ValueError, match=r"workers must be an integer >= 1 or None, got 0"):
        check_count(0, "workers", optional=True)


@pytest.mark.parametrize(
    ("value", "hint", "expected"),
    [
        (1, float, 1.0),
        ([1, 2], tuple[float, ...], (1.0, 2.0)),
        ([1, "a"], tuple[int, str], (1, "a")),
        (None, int | None, None),
        ({"a": 1}, dict[str, float], {"a": 1.0}),
        ({"a": [1]}, dict[str, Any], {"a": [1]}),
    ],
)
def test_json_values_are_converted(value, hint, expected):
    assert coerce(value, hint) == expected


@pytest.mark.parametrize(
    ("value", "hint", "message"),
    [
        (True, int, "an integer"),
        (True, float, "a finite number"),
        (math.nan, float, "a finite number"),
        ("1", float, "a finite number"),
        ([1, "x"], tuple[float, ...], "a list of finite numbers"),
        ([1], tuple[int, int], "a list of integers"),
        ({"a": "x"}, dict[str, float], "an object of finite numbers"),
        (3, str | None, "a string or null"),
    ],
)
def test_mismatches_say_what_was_expected(value, hint, message):
    with pytest.raises(TypeMismatch, match=message):
        coerce(value, hint)


def test_nonfinite_mode_reads_null_as_nan():
    assert math.isnan(coerce(None, float, nonfinite=True)) and coerce(math.inf, float, nonfinite=True) == math.inf
