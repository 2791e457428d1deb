from __future__ import annotations

import pytest

from ioc_bench.bench.conditions import CONDITIONS, Condition, register_condition
from ioc_bench.bench.suites import SUITES, Suite, get_suite


def test_paper_suite_is_four_weight_sets_by_six_conditions():
    cases = get_suite("paper").cases("log-barrier")
    assert len(cases) == 24 and len({c.key for c in cases}) == 24
    assert {c.condition for c in cases} == set(CONDITIONS)


def test_smoke_is_small_and_paper_3seeds_has_three_seeds():
    assert len(get_suite("smoke").cases("x")) <= 4
    assert get_suite("paper-3seeds").seeds == (0, 1, 2)


def test_bad_suites_and_unknown_names():
    with pytest.raises(ValueError, match="unknown condition"):
        Suite("bad", "", ("nominal",), ("nope",))
    with pytest.raises(ValueError, match="valid: smoke"):
        get_suite("nope")


def test_a_user_condition_needs_no_runner_change(monkeypatch):
    monkeypatch.setattr("ioc_bench.bench.conditions.CONDITIONS", dict(CONDITIONS))
    from ioc_bench.bench import conditions

    cond = register_condition(Condition("noise-10", "10 % noise", noise=0.10))
    assert conditions.get_condition("noise-10") is cond
    suite = Suite("mine", "", ("nominal",), ("noise-10",))
    assert suite.cases("log-barrier")[0].condition == "noise-10"
    assert "mine" not in SUITES
