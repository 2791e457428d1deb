from __future__ import annotations

import pytest

from ioc_bench.bench.conditions import CONDITIONS, Condition, register_condition
from ioc_bench.bench.suites import SUITES, Suite, get_suite


def test_paper_suite_is_four_weight_sets_by_the_papers_conditions_and_noise_kinematics():
    cases = get_suite("paper").cases("log-barrier")
    assert len(cases) == 28 and len({c.key for c in cases}) == 28
    paper = {"ideal", "ideal-fast", "noise", "mass", "speed", "distractor"}
    assert {c.condition for c in cases} == paper | {"noise-kinematics"}
    assert set(CONDITIONS) > paper


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

    cond = register_condition(Condition("noise-20", "20 % noise", noise=0.20))
    assert conditions.get_condition("noise-20") is cond
    suite = Suite("mine", "", ("nominal",), ("noise-20",))
    assert suite.cases("log-barrier")[0].condition == "noise-20"
    assert "mine" not in SUITES
