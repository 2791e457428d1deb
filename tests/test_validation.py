"""Checks of values from outside: seeds, counts, and JSON values against type annotations."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
import pytest

from ioc_bench.validation import (
    MAX_MESSAGE,
    MIN_WORD,
    TypeMismatch,
    check_count,
    check_seed,
    coerce,
    json_fields,
    one_line,
    short_word,
)


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


def test_one_line_shortens_the_longest_words_so_the_sentence_survives():
    deep = "/scratch/" + "/".join(["folder" * 8] * 6)
    message = f"cannot write {deep}/r.json: {deep} leads out of {deep}/x (move it away, or use another --out)"
    line = one_line(message)
    assert len(line) <= MAX_MESSAGE and "leads out of" in line and "move it away" in line and " ... " not in line
    assert line.startswith("cannot write /scratch/folder") and "/r.json:" in line
    short = f"cannot write {deep}/r.json"
    assert one_line(short) == short  # a line that fits keeps its paths whole


def test_one_line_cuts_in_the_middle_what_is_still_too_long():
    line = one_line(" ".join(["word"] * 200))
    assert len(line) <= MAX_MESSAGE and " ... " in line and "\n" not in line
    words = one_line(" ".join(["x" * 300] * 20)).split()
    assert all(len(w) <= MIN_WORD for w in words if w != "...")
    assert short_word("abcdefghij", 8) == "ab...hij" and short_word("abc", 8) == "abc"


@dataclass(frozen=True)
class _Record:
    name: str
    values: tuple[float, ...]
    note: str = ""


def test_json_fields_checks_each_field_against_its_annotation():
    data = {"name": "a", "values": [1, None], "note": "x", "file_key": "k"}
    values = json_fields(_Record, data, extra={"file_key": str})
    assert values["name"] == "a" and values["note"] == "x" and "file_key" not in values
    assert values["values"][0] == 1.0 and math.isnan(values["values"][1])  # NaN is stored as null
    assert json_fields(_Record, {"name": "a", "values": []}, hints={"values": Any})["values"] == []


@pytest.mark.parametrize(
    ("data", "where", "message"),
    [
        ([1], "", "expected a JSON object, got list"),
        ({"name": "a"}, "", "missing field(s) values"),
        ({"name": "a", "values": [], "surprise": 1}, "", "unknown field(s) surprise"),
        ({"name": 3, "values": []}, "", "name must be a string, got 3"),
        ({"name": "a", "values": [], "file_key": 3}, "", "file_key must be a string, got 3"),
        ({"name": "a"}, "scores[T03]", "scores[T03]: missing field(s) values"),
        ({"name": "a", "values": "x"}, "scores[T03]", 'scores[T03].values must be a list of numbers, got "x"'),
    ],
)
def test_json_fields_names_the_first_problem_and_where_it_is(data, where, message):
    with pytest.raises(ValueError) as info:
        json_fields(_Record, data, where, extra={"file_key": str})
    assert str(info.value) == message
