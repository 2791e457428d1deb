"""The human track's score: the skill formula, the case lists, and the scorer on a synthetic
person whose true weights are known."""

from __future__ import annotations

import dataclasses
import math

import pytest

from ioc_bench.human import WbdsData, load_step
from ioc_bench.human.observe import leg_angles
from ioc_bench.human.track import (
    BUILTINS,
    HUMAN,
    HUMAN_SMOKE,
    NOMINAL,
    SHIPPED_SUBJECTS,
    SPEED_CODES,
    HumanCaseSpec,
    run_floors,
    run_human_case,
    score_weights,
    skill_score,
    summarize,
    summary_markdown,
)
from ioc_bench.ioc.registry import algorithms
from ioc_bench.optimize import optimize_gait


@pytest.mark.parametrize(
    ("method", "nominal", "floor", "skill"),
    [
        (8.0, 10.0, 6.0, 0.5),  # half of what could be gained over the nominal
        (6.0, 10.0, 6.0, 1.0),  # the method is the floor
        (10.0, 10.0, 6.0, 0.0),  # as good as the nominal
        (12.0, 10.0, 6.0, -0.5),  # worse than the nominal, in units of the possible gain
        (9.0, 9.0, 9.0, 0.0),  # nominal is the floor and the method matches it
    ],
)
def test_skill_on_hand_made_numbers(method: float, nominal: float, floor: float, skill: float) -> None:
    assert skill_score(method, nominal, floor) == pytest.approx(skill)


def test_skill_is_undefined_when_nothing_could_be_gained_and_the_method_lost() -> None:
    assert math.isnan(skill_score(12.0, 9.0, 9.0))
    assert math.isnan(skill_score(float("nan"), 9.0, 8.0))  # a failed solve


def test_a_floor_above_the_method_or_the_nominal_is_refused() -> None:
    with pytest.raises(ValueError, match="floor"):
        skill_score(8.0, 10.0, 8.5)
    with pytest.raises(ValueError, match="floor"):
        skill_score(12.0, 10.0, 10.5)


def test_case_specs_refuse_bad_input() -> None:
    with pytest.raises(ValueError, match="also a predicted speed"):
        HumanCaseSpec("WBDS01", "T05", ("T04", "T05"), "bilevel")
    with pytest.raises(ValueError, match="repeated"):
        HumanCaseSpec("WBDS01", "T05", ("T04", "T04"), "bilevel")
    with pytest.raises(ValueError, match="unknown subject code"):
        HumanCaseSpec("subject1", "T05", ("T04",), "bilevel")
    with pytest.raises(ValueError, match="unknown speed code"):
        HumanCaseSpec("WBDS01", "T05", ("T10",), "bilevel")
    with pytest.raises(ValueError, match="sequence of speed codes"):
        HumanCaseSpec("WBDS01", "T05", "T04", "bilevel")
    with pytest.raises(ValueError):
        HumanCaseSpec("WBDS01", "T05", ("T04",), "bilevel", starts=0)
    with pytest.raises(ValueError, match="training speed is repeated"):
        HumanCaseSpec("WBDS01", "T05", ("T04",), "bilevel", also_train=("T05",))
    with pytest.raises(ValueError, match="T06 is also a predicted speed"):
        HumanCaseSpec("WBDS01", "T05", ("T04", "T06"), "bilevel", also_train=("T06",))


def test_several_training_speeds() -> None:
    spec = HumanCaseSpec("WBDS01", "T04", ("T03", "T06"), "bilevel", also_train=("T05",))
    assert spec.training == ("T04", "T05") and spec.speeds == ("T04", "T05", "T03", "T06")
    assert spec.key == "bilevel/WBDS01_T04+T05__predict-T03-T06__seed0"
    assert spec.identity()["also_train"] == ["T05"] and "also_train" not in HUMAN_SMOKE[0].identity()


def test_an_algorithm_for_one_trial_given_several_is_a_recorded_failure() -> None:
    """single-level takes one trial: with two training speeds the case fails at once, with
    the reason, and nothing is solved."""
    spec = HumanCaseSpec("WBDS01", "T05", ("T04",), "single-level", also_train=("T06",))
    result = run_human_case(spec)
    assert result.failed and "multi_trial is False" in result.estimate.reason
    assert result.estimate.n_solves == 0 and result.speeds == {}
    record = result.to_dict()
    assert record["fit"] is None and record["predictions"] == {} and record["also_train"] == ["T06"]


def test_the_case_lists() -> None:
    assert [(s.subject, s.train, s.predict, s.algorithm) for s in HUMAN_SMOKE] == [
        ("WBDS01", "T05", ("T04",), "inverse-kkt"),
        ("WBDS01", "T05", ("T04",), "bilevel"),
    ]
    assert set(SHIPPED_SUBJECTS) == set(WbdsData().subjects())
    assert set(BUILTINS) <= set(algorithms())
    assert len(HUMAN) == len(SHIPPED_SUBJECTS) * len(SPEED_CODES) * len(BUILTINS)
    assert len({s.key for s in HUMAN}) == len(HUMAN)
    for spec in HUMAN:
        assert sorted(spec.speeds) == list(SPEED_CODES)


def test_the_scorer_refuses_steps_of_another_subject() -> None:
    mine, theirs = load_step("WBDS01", "T05"), load_step("WBDS02", "T04")
    with pytest.raises(ValueError, match="different subjects"):
        score_weights((1, 1, 1), {"T05": mine, "T04": theirs})
    with pytest.raises(ValueError, match="is WBDS01's step at T05"):
        score_weights((1, 1, 1), {"T04": mine})
    with pytest.raises(ValueError):
        score_weights((1, 1), {"T05": mine})
    with pytest.raises(ValueError):
        score_weights((1, 1, 1), {"T05": mine}, floor_weights=("1,x,0",))


def test_a_synthetic_person_scores_the_true_weights_best_and_wrong_weights_worst() -> None:
    """A "person" who is the walker's optimum for known weights at a human task: the true
    weights reproduce the step (RMSE 0, skill 1); dtau-only weights, far from the knee-
    dominated truth, fit worse than the nominal (negative skill)."""
    step = load_step("WBDS01", "T04")
    truth = (1.0, 4.0, 0.0)
    demo = optimize_gait(truth, step.params, step.task, starts=1, seed=0, workers=1, verify=False)
    assert demo.solver.success
    person = dataclasses.replace(step, angles=leg_angles(demo.trajectory))
    right = score_weights(truth, {"T04": person}, starts=1, floor_weights=())["T04"]
    wrong = score_weights((0.0, 0.0, 1.0), {"T04": person}, starts=1, floor_weights=("1,4,0",))["T04"]
    nominal = right.references[NOMINAL].rmse_deg
    assert right.estimate.rmse_deg < 1e-6 < nominal
    assert right.floor_rmse_deg == right.estimate.rmse_deg and right.floor_label == "estimate"
    assert right.skill == pytest.approx(1.0)
    assert wrong.references[NOMINAL] is right.references[NOMINAL]  # solved once, shared
    assert wrong.estimate.rmse_deg > nominal
    assert wrong.floor_label == "1,4,0" and wrong.floor_rmse_deg < 1e-6  # the truth, as a floor direction
    assert wrong.skill == pytest.approx((nominal - wrong.estimate.rmse_deg) / nominal) and wrong.skill < 0


def _record(algorithm: str, fit: float, pred: float, nominal: float, skill: float | None) -> dict:
    refs = {NOMINAL: {"rmse_deg": nominal}}
    return {
        "algorithm": algorithm,
        "subject": "WBDS01",
        "train": "T05",
        "status": "converged",
        "wall_time": 1.0,
        "scoring_time": 2.0,
        "fit": {"fit_rmse_deg": fit, "nominal_rmse_deg": 9.0, "skill": 0.0, "references": {NOMINAL: {"rmse_deg": 9.0}}},
        "predictions": {
            "T04": {"prediction_rmse_deg": pred, "nominal_rmse_deg": nominal, "skill": skill, "references": refs}
        },
    }


def test_the_run_summary_uses_the_lowest_rmse_of_any_case_as_floor() -> None:
    """At T04 one algorithm predicts 6 deg, the other 12, against a nominal of 10: over the
    run the floor is 6, so the second's skill is (10 - 12) / (10 - 6) = -0.5, although its
    own case (floor = nominal) could not define one."""
    records = [_record("a", 7.0, 6.0, 10.0, 1.0), _record("b", 8.0, 12.0, 10.0, None)]
    assert run_floors(records) == {("WBDS01", "T05"): 7.0, ("WBDS01", "T04"): 6.0}
    summary = summarize(records)
    assert summary["a"]["beat_nominal"] == 1 and summary["b"]["beat_nominal"] == 0
    assert summary["b"]["median_skill_run_floor"] == pytest.approx(-0.5)
    assert math.isnan(summary["b"]["median_skill"])
    assert summary["a"]["fit_rmse_deg"] == 7.0 and summary["a"]["time_s"] == 3.0
    failed = {"algorithm": "a", "subject": "WBDS01", "train": "T05", "status": "failed", "fit": None, "predictions": {}}
    assert summarize([*records, failed])["a"]["failed"] == 1
    table = summary_markdown(summary).splitlines()
    assert len(table) == 4 and table[2].startswith("| a | 1 | 0 | 7.00 | 6.00 | 1 of 1 |")
    assert table[3].startswith("| b | 1 | 0 | 8.00 | 12.00 | 0 of 1 | - | -0.50 |")
