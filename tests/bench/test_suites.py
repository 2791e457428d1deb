from __future__ import annotations

import pytest

from ioc_bench.synthetic.case import CaseSpec
from ioc_bench.synthetic.conditions import CONDITIONS, Condition, register_condition
from ioc_bench.synthetic.suites import SUITES, Suite, get_suite


def test_paper_suite_is_four_weight_sets_by_the_papers_conditions_noise_kinematics_and_multi_trial():
    cases = get_suite("paper").cases("log-barrier")
    assert len(cases) == 36 and len({c.key for c in cases}) == 36
    paper = {"ideal", "ideal-fast", "noise", "mass", "speed", "distractor"}
    assert {c.condition for c in cases} == paper | {"noise-kinematics", "multi-speed", "multi-speed-noise"}
    assert set(CONDITIONS) > paper


def test_multi_trial_cases_observe_both_speeds_and_share_the_first_trial():
    multi = CaseSpec("x", "penalize-knee", "multi-speed-noise", 1)
    single = CaseSpec("x", "penalize-knee", "noise", 1)
    speeds = [r.task.speed for r in multi.demo_requests()]
    assert speeds == [0.27, 0.34] and multi.demo_request() == single.demo_request()
    assert multi.transfer_request() is None and single.transfer_request().task.speed == 0.34


def test_compass_suites_run_the_compass_model_with_its_own_weight_sets():
    cases = get_suite("compass-paper").cases("x")
    assert {c.model for c in cases} == {"compass"} and {c.weight_set for c in cases} == {
        "nominal",
        "penalize-hip",
        "penalize-dtau",
    }
    distractor = next(c for c in cases if c.condition == "distractor")
    assert distractor.features == ("hip", "dtau", "torso", "steplen", "footheight")
    assert distractor.key.endswith("__model-compass")
    with pytest.raises(ValueError, match="penalize-knee"):
        CaseSpec("x", "penalize-knee", "ideal", 0, model="compass")


def test_smoke_is_small_and_paper_3seeds_has_three_seeds():
    assert len(get_suite("smoke").cases("x")) <= 4
    assert get_suite("paper-3seeds").seeds == (0, 1, 2)


def test_bad_suites_and_unknown_names():
    with pytest.raises(ValueError, match="unknown condition"):
        Suite("bad", "", ("nominal",), ("nope",))
    with pytest.raises(ValueError, match="valid: smoke"):
        get_suite("nope")


def test_a_user_condition_needs_no_runner_change(monkeypatch):
    monkeypatch.setattr("ioc_bench.synthetic.conditions.CONDITIONS", dict(CONDITIONS))
    from ioc_bench.synthetic import conditions

    cond = register_condition(Condition("noise-20", "20 % noise", noise=0.20))
    assert conditions.get_condition("noise-20") is cond
    suite = Suite("mine", "", ("nominal",), ("noise-20",))
    assert suite.cases("log-barrier")[0].condition == "noise-20"
    assert "mine" not in SUITES


def test_the_energetics_suites_weigh_work_and_the_collision_loss():
    """``energetics-ideal``: demonstrations made in the energetics basis (their own cache
    entries), its six weight sets, the IOC weighing the five features; ``energetics-distractor``:
    the paper's demonstrations, with work and collision offered at true weight 0."""
    ideal = get_suite("energetics-ideal").cases("x")
    assert [c.weight_set for c in ideal] == [
        "nominal", "penalize-hip", "penalize-knee", "penalize-dtau", "penalize-work", "penalize-collision"
    ]  # fmt: skip
    work = ideal[4]
    assert work.features == ("hip", "knee", "dtau", "work", "collision")
    assert work.key == "x/penalize-work__ideal__seed0__basis-energetics"
    assert work.true_over_features().argmax() == 3
    request = work.demo_request()
    assert request.features == ("hip", "knee", "dtau", "torso", "steplen", "footheight", "work", "collision")
    assert request.weights[6] == max(request.weights) and request.weights[3:6].tolist() == [0, 0, 0]
    plain = CaseSpec("x", "nominal", "ideal", 0).demo_request()
    assert ideal[0].demo_request().key != plain.key and plain.features is None
    distractor = get_suite("energetics-distractor").cases("x")
    assert {c.condition for c in distractor} == {"distractor-energetics"}
    assert distractor[0].features == ("hip", "knee", "dtau", "work", "collision")
    assert distractor[0].true_over_features()[3:].tolist() == [0, 0]
    assert distractor[0].demo_request() == plain  # the paper's demonstration, shared


def test_a_weight_set_of_another_basis_is_refused_naming_the_valid_ones():
    with pytest.raises(ValueError, match="unknown weight set 'penalize-work'"):
        CaseSpec("x", "penalize-work", "ideal", 0)
    with pytest.raises(ValueError, match="unknown cost basis"):
        CaseSpec("x", "nominal", "ideal", 0, basis="rich")


def test_the_effort_work_suite_weighs_work_beside_the_efforts():
    cases = get_suite("effort-work-ideal").cases("x")
    assert [c.weight_set for c in cases] == [
        "nominal",
        "penalize-hip",
        "penalize-knee",
        "penalize-dtau",
        "penalize-work",
    ]
    assert {c.features for c in cases} == {("hip", "knee", "dtau", "work")}
    assert cases[-1].demo_request().features == ("hip", "knee", "dtau", "torso", "steplen", "footheight", "work")


def test_the_ankle_feet_suites_weigh_the_ankles_on_their_own_model():
    """``ankle-feet-ideal``: the model's own effort basis (the ankle's effort among them);
    ``ankle-feet-effort-work-ideal``: the effort-work basis on that model. Built, not run."""
    effort = get_suite("ankle-feet-ideal").cases("x")
    assert [c.weight_set for c in effort] == [
        "nominal", "penalize-hip", "penalize-knee", "penalize-ankle", "penalize-dtau"
    ]  # fmt: skip
    assert {(c.model, c.basis, c.condition) for c in effort} == {("ankle-feet", "effort", "ideal")}
    ankle = effort[3]
    assert ankle.cost_features == ("hip", "knee", "ankle", "dtau") and set(ankle.features) == set(ankle.cost_features)
    assert ankle.true_over_features()[ankle.features.index("ankle")] == max(ankle.true_over_features())
    assert ankle.key == "x/penalize-ankle__ideal__seed0__model-ankle-feet"
    request = ankle.demo_request()
    assert request.model == "ankle-feet" and request.features is None and request.weights.argmax() == 2
    work = get_suite("ankle-feet-effort-work-ideal").cases("x")
    assert [c.weight_set for c in work] == [
        "nominal", "penalize-hip", "penalize-knee", "penalize-ankle", "penalize-dtau", "penalize-work"
    ]  # fmt: skip
    assert {(c.model, c.basis) for c in work} == {("ankle-feet", "effort-work")}
    assert work[-1].cost_features == ("hip", "knee", "ankle", "dtau", "work")
    assert work[-1].key == "x/penalize-work__ideal__seed0__model-ankle-feet__basis-effort-work"
    assert work[-1].demo_request().features == (
        "hip", "knee", "ankle", "dtau", "torso", "steplen", "footheight", "work"
    )  # fmt: skip
