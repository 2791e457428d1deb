"""Human-track cases: their identity and designs, the score of a speed on a person whose true
weights are known, the record read back checked, and the run's summary."""

from __future__ import annotations

import dataclasses
import json
import math

import numpy as np
import pytest

from ioc_bench.human import WbdsData, load_step
from ioc_bench.human.board import markdown
from ioc_bench.human.case import HumanCaseSpec, ReferenceStep, parse_record, score_speed
from ioc_bench.human.observe import leg_angles
from ioc_bench.human.scoring import NOMINAL, beats, skill_score, solve_step
from ioc_bench.human.suites import HUMAN_SUITES, SHIPPED_SUBJECTS, SPEED_CODES
from ioc_bench.human.summary import pooled_r2, run_floors, summarize, weight_spread
from ioc_bench.optimize import optimize_gait
from ioc_bench.provenance import provenance


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


def test_a_loss_to_the_nominal_is_a_loss_even_where_the_skill_is_undefined() -> None:
    assert math.isnan(skill_score(12.0, 9.0, 9.0)) and beats(12.0, 9.0) is False
    assert beats(8.0, 9.0) is True and beats(float("nan"), 9.0) is None  # a failed solve is neither
    with pytest.raises(ValueError, match="floor"):
        skill_score(8.0, 10.0, 8.5)


def test_case_specs_refuse_bad_input() -> None:
    bad = [
        ({"predict": ("T04", "T05")}, "also a predicted speed"),
        ({"predict": ("T04", "T04")}, "repeated"),
        ({"subject": "subject1"}, "unknown subject code"),
        ({"predict": ("T10",)}, "unknown speed code"),
        ({"predict": "T04"}, "must be a sequence"),
        ({"starts": 0}, "starts"),
        ({"also_train": ("T05",)}, "training speed is repeated"),
        ({"population": ("WBDS01",)}, "in its own population"),
        ({"population": ("WBDS02", "WBDS02")}, "population subject is repeated"),
        ({"model": "compass"}, "human steps map to"),
        ({"floor_weights": ("1,x,0",)}, "1,x,0"),
        ({"task": "step"}, "unknown task 'step'"),
        ({"basis": "rich"}, "unknown cost basis 'rich'"),
    ]
    for change, message in bad:
        fields = {"subject": "WBDS01", "train": "T05", "predict": ("T04",), "algorithm": "bilevel"} | change
        with pytest.raises(ValueError, match=message):
            HumanCaseSpec(**fields)


def test_designs_name_their_files_and_their_roles() -> None:
    two = HumanCaseSpec("WBDS01", "T04", ("T03", "T06"), "bilevel", also_train=("T05",))
    assert two.design == "two speeds" and two.scored == ("T04", "T05", "T03", "T06")
    assert two.key == "bilevel/WBDS01__train-T04+T05__predict-T03-T06__seed0"
    assert [two.role(c) for c in two.scored] == ["fit", "fit", "prediction", "prediction"]
    pop = HumanCaseSpec("WBDS01", "T05", SPEED_CODES, "bilevel", population=("WBDS02", "WBDS03"))
    assert (
        pop.design == "population"
        and pop.scored == SPEED_CODES
        and {pop.role(c) for c in SPEED_CODES} == {"prediction"}
    )
    assert pop.key == "bilevel/WBDS01__train-T05__from-WBDS02+WBDS03__predict-T03-T04-T05-T06__seed0"
    assert HumanCaseSpec("WBDS01", "T05", ("T04",), "bilevel", data="/elsewhere").key == (
        "bilevel/WBDS01__train-T05__predict-T04__seed0"  # where the data lie is not what the case is
    )


def test_the_suites() -> None:
    assert set(SHIPPED_SUBJECTS) == set(WbdsData().subjects())
    human = HUMAN_SUITES["human"].cases("bilevel")
    assert len(human) == len(HUMAN_SUITES["human"]) == 27 and len({s.key for s in human}) == 27
    designs = [s.design for s in human]
    assert {d: designs.count(d) for d in set(designs)} == {
        "one speed": 12, "two speeds": 6, "leave one out": 6, "population": 3,
    }  # fmt: skip
    for spec in human:
        assert set(spec.scored) | set(spec.training) == set(SPEED_CODES)
    assert [s.key for s in HUMAN_SUITES["human-smoke"].cases("inverse-kkt")] == [
        "inverse-kkt/WBDS01__train-T05__predict-T04__seed0__task-speed"
    ]
    assert [s.key for s in HUMAN_SUITES["human-rolling-feet"].cases("inverse-kkt")] == [
        "inverse-kkt/WBDS01__train-T05__predict-T04__seed0__model-rolling-feet__task-speed"
    ]
    given = HUMAN_SUITES["human-given-step"].cases("bilevel")
    assert {s.task for s in given} == {"speed-and-step"} and {s.task for s in human} == {"speed"}
    assert [s.key for s in given] == [s.key.replace("__task-speed", "") for s in human]
    on_feet = HUMAN_SUITES["human-smoke"].cases("bilevel", model="rolling-feet")
    assert [s.model for s in on_feet] == ["rolling-feet"]
    with pytest.raises(ValueError, match="human steps map to"):
        HUMAN_SUITES["human-smoke"].cases("bilevel", model="compass")


def test_an_algorithm_for_one_trial_given_several_is_a_recorded_failure(one_trial_algorithm) -> None:
    spec = HumanCaseSpec("WBDS01", "T05", ("T04",), one_trial_algorithm, also_train=("T06",))
    record = spec.run({})
    assert record.failed and "multi_trial is False" in record.reason
    assert record.n_solves == 0 and record.scores == {}
    assert record.provenance == provenance() and spec.failure("timed out").provenance == provenance()
    again = parse_record(json.loads(json.dumps(record.to_dict(), allow_nan=True).replace("NaN", "null")))
    assert again.failed and again.reason == record.reason and np.all(np.isnan(again.weights))
    assert again.provenance == record.provenance


@pytest.fixture(scope="module")
def known_person():
    """A "person" who is the walker's optimum for (1, 4, 0) at WBDS01's T04 and T05 tasks."""
    steps, truth = {}, (1.0, 4.0, 0.0)
    for code in ("T04", "T05"):
        step = load_step("WBDS01", code)
        demo = optimize_gait(truth, step.params, step.task, starts=1, seed=0, workers=1, verify=False)
        assert demo.solver.success
        steps[code] = dataclasses.replace(step, angles=leg_angles(demo.trajectory))
    return steps, truth


def test_the_true_weights_score_best_and_the_copy_and_adaptation_are_the_persons(known_person) -> None:
    steps, truth = known_person
    estimate = {code: solve_step(truth, steps[code], 1, 0, "estimate") for code in steps}
    refs = {code: {NOMINAL: ReferenceStep(NOMINAL, steps[code], 1, 0).prepare()} for code in steps}
    score = score_speed("T04", "prediction", "T05", steps, estimate, refs)
    assert score.rmse_deg < 1e-6 < score.nominal_rmse_deg and score.skill == pytest.approx(1.0)
    assert score.floor_weights == "estimate" and score.beats_nominal is True
    change = np.degrees(np.sqrt(np.mean((steps["T04"].angles - steps["T05"].angles) ** 2)))
    assert score.copy_rmse_deg == pytest.approx(change) == score.copy_adaptation_deg
    assert score.adaptation_deg < 1e-6 and score.beats_copy is True  # the truth changes as the person does
    wrong = {code: solve_step((0.0, 0.0, 1.0), steps[code], 1, 0, "estimate") for code in steps}
    worse = score_speed("T04", "prediction", "T05", steps, wrong, refs)
    assert worse.rmse_deg > worse.nominal_rmse_deg and worse.beats_nominal is False
    assert math.isnan(worse.skill)  # the nominal is the floor of what was solved: nothing to scale a loss by
    with_truth = {code: refs[code] | {"1,4,0": estimate[code]} for code in steps}  # the truth as a floor direction
    worse = score_speed("T04", "prediction", "T05", steps, wrong, with_truth)
    assert worse.floor_weights == "1,4,0" and worse.skill < 0


def test_a_reference_step_is_kept_and_checked_against_its_key(known_person, tmp_path, monkeypatch) -> None:
    monkeypatch.setenv("IOC_BENCH_CACHE", str(tmp_path))
    steps, _ = known_person
    request = ReferenceStep(NOMINAL, steps["T04"], 1, 0)
    first = request.prepare()
    entry = tmp_path / "human-references" / f"{request.key}.json"
    assert entry.is_file() and request.prepare().objective == first.objective
    other = ReferenceStep(NOMINAL, steps["T05"], 1, 0)
    entry.rename(tmp_path / "human-references" / f"{other.key}.json")  # T04's step filed under T05's key
    assert other.prepare().objective != first.objective  # solved again, not read back


def _record(case: HumanCaseSpec, rmse: dict[str, float], nominal: float = 10.0):
    """A made-up record of ``case``, consistent with its own numbers."""
    from ioc_bench.human.record import HumanResult, SpeedScore

    def score(code: str) -> SpeedScore:
        method, copy = rmse[code], 3.0 if case.role(code) == "prediction" else math.nan
        floor = min(method, nominal)
        source = case.train if case.role(code) == "prediction" else ""
        return SpeedScore(
            code, case.role(code), 0.3, 0.6, "Solve_Succeeded", 1.0, method, nominal, floor,
            "estimate" if method <= nominal else NOMINAL, skill_score(method, nominal, floor), beats(method, nominal),
            source, copy, beats(method, copy) if source else None, 4.0 if source else math.nan, copy,
            5.0 if source else math.nan, 0.1, 0.2, 1.0,
        )  # fmt: skip

    identity = {f: getattr(case, f) for f in HumanCaseSpec.identity_fields()}
    return HumanResult(
        **identity, family="bilevel", features=case.features, status="converged", reason="",
        weights=(0.6, 0.8, 0.0), wall_time=1.0, n_solves=2, scoring_time=2.0,
        scores={code: score(code) for code in case.scored},
    )  # fmt: skip


_PROVENANCE = {"commit": "0123456789abcdef0123456789abcdef01234567", "dirty": False, "versions": {"numpy": "2.4.6"}}


def test_a_record_read_back_is_checked_for_consistency() -> None:
    case = HumanCaseSpec("WBDS01", "T05", ("T04",), "bilevel")
    record = _record(case, {"T05": 6.0, "T04": 8.0})
    data = json.loads(json.dumps(record.to_dict()))
    assert json.dumps(parse_record(data).to_dict()) == json.dumps(record.to_dict())  # NaN compares equal here
    edits = [
        (lambda d: d["scores"]["T04"].update(skill=99.0), "skill is 99.0"),
        (lambda d: d["scores"]["T04"].update(rmse_deg=-5.0), "non-negative"),
        (lambda d: d["scores"]["T04"].update(rmse_deg="x"), r"scores\[T04\]\.rmse_deg must be a number"),
        (lambda d: d["scores"]["T04"].pop("rmse_deg"), r"scores\[T04\]: missing field\(s\) rmse_deg"),
        (lambda d: d.pop("weights"), r"missing field\(s\) weights"),
        (lambda d: d.update(surprise=1), r"unknown field\(s\) surprise"),
        (lambda d: d.update(weights=[5, 5, 5]), "unit norm"),
        (lambda d: d["scores"]["T04"].update(floor_rmse_deg=1.0), "lowest RMSE"),
        (lambda d: d["scores"]["T04"].update(beats_copy=True), "beats_copy"),
        (lambda d: d["scores"].pop("T05"), "the case's speeds"),
        (lambda d: d.update(subject="WBDS99"), None),
        (lambda d: d.update(track="synthetic"), "track"),
        (lambda d: d["scores"]["T04"].update(continued_from="T05", change_r2=0.5), "change_r2 is 0.5"),
        (lambda d: d["scores"]["T04"].update(step_length_error=-0.1), "step_length_error must be a non-negative"),
        (lambda d: d.update(task="walk"), "unknown task 'walk'"),
        (lambda d: d.update(provenance={"commit": "abc"}), r"provenance must be \{\} or have the fields"),
        (lambda d: d.update(provenance=_PROVENANCE | {"commit": "xyz"}), "provenance.commit must be null or 40"),
        (lambda d: d.update(provenance=_PROVENANCE | {"dirty": "no"}), "provenance.dirty must be null, true"),
        (lambda d: d.update(provenance=_PROVENANCE | {"versions": {"numpy": 2}}), "provenance.versions must map"),
        (lambda d: d.update(provenance=[]), "provenance must be an object"),
    ]
    for edit, message in edits:
        spoilt = json.loads(json.dumps(data))
        edit(spoilt)
        if message is None:  # another valid case: the results reader compares it with the file's name
            assert parse_record(spoilt).subject == "WBDS99"
            continue
        with pytest.raises(ValueError, match=message):
            parse_record(spoilt)


def test_the_run_summary_takes_its_floor_from_every_case_and_counts_losses() -> None:
    """At T04 one algorithm predicts 6 deg, the other 12, against a nominal of 10: the run's
    floor is 6, so the second's skill is (10 - 12) / (10 - 6) = -0.5, and it loses to the
    nominal and to the copy (3 deg)."""
    a = _record(HumanCaseSpec("WBDS01", "T05", ("T04",), "a"), {"T05": 7.0, "T04": 6.0})
    b = _record(HumanCaseSpec("WBDS01", "T05", ("T04",), "b"), {"T05": 8.0, "T04": 12.0})
    assert run_floors([a, b]) == {("WBDS01", "T05"): 7.0, ("WBDS01", "T04"): 6.0}
    rows = {r["algorithm"]: r for r in summarize([a, b])}
    assert rows["a"]["beat_nominal"] == 1 and rows["b"]["beat_nominal"] == 0
    assert rows["b"]["median_skill_run_floor"] == pytest.approx(-0.5)
    assert rows["a"]["beat_copy"] == rows["b"]["beat_copy"] == 0 and rows["a"]["copy_rmse_deg"] == 3.0
    assert rows["a"]["fit_rmse_deg"] == 7.0 and rows["a"]["time_s"] == 3.0 and rows["a"]["design"] == "one speed"
    table = markdown([a, b])
    assert "| a | speed-and-step | one speed | 7.00 | 6.00 | 10.00 | 3.00 | 1/1 | 0/1 |" in table


def test_the_summary_keeps_each_models_records_apart() -> None:
    """The rolling-feet case's 4 deg at T04 is not the walker's floor there: each model's
    skill is taken against its own run floor, in its own row."""
    walker = _record(HumanCaseSpec("WBDS01", "T05", ("T04",), "a"), {"T05": 7.0, "T04": 6.0})
    feet = _record(HumanCaseSpec("WBDS01", "T05", ("T04",), "a", model="rolling-feet"), {"T05": 5.0, "T04": 4.0})
    rows = summarize([feet, walker])
    assert [(r["algorithm"], r["model"]) for r in rows] == [("a", "walker"), ("a", "rolling-feet")]
    assert [r["median_skill_run_floor"] for r in rows] == [pytest.approx(1.0), pytest.approx(1.0)]
    assert [r["prediction_rmse_deg"] for r in rows] == [6.0, 4.0]
    table = markdown([walker, feet])
    assert "| a | speed-and-step | one speed | 7.00 | 6.00 |" in table
    assert "| a (rolling-feet) | speed-and-step | one speed | 5.00 | 4.00 |" in table


def test_the_summary_orders_rows_by_algorithm_then_design_whatever_order_the_files_came_in() -> None:
    two = _record(
        HumanCaseSpec("WBDS01", "T04", ("T03", "T06"), "a", also_train=("T05",)),
        {"T04": 7.0, "T05": 7.0, "T03": 6.0, "T06": 6.0},
    )
    one = _record(HumanCaseSpec("WBDS01", "T05", ("T04",), "a"), {"T05": 7.0, "T04": 6.0})
    other = _record(HumanCaseSpec("WBDS01", "T05", ("T04",), "0-first"), {"T05": 7.0, "T04": 6.0})
    rows = summarize([two, one, other])
    assert [(r["algorithm"], r["design"]) for r in rows] == [
        ("0-first", "one speed"),
        ("a", "one speed"),
        ("a", "two speeds"),
    ]


def test_the_change_is_pooled_over_predictions_by_its_squares() -> None:
    """Two predictions whose person's change is 1 and 3 deg, predicted with errors of 1 and
    0 deg: 1 - (1 + 0) / (1 + 9) = 0.9 (the mean of the two R^2s, 0 and 1, would be 0.5)."""
    assert pooled_r2([(1.0, 1.0), (0.0, 3.0)]) == pytest.approx(0.9)
    assert pooled_r2([(3.0, 3.0), (1.0, 1.0)]) == 0.0  # copying: the error is the change itself
    assert math.isnan(pooled_r2([(math.nan, 1.0)])) and math.isnan(pooled_r2([]))
    case = HumanCaseSpec("WBDS01", "T05", ("T04",), "a")
    record = _record(case, {"T05": 7.0, "T04": 6.0})  # adaptation 4 deg, the person's change 3
    (row,) = summarize([record])
    assert row["change_r2"] == pytest.approx(1 - 16 / 9) and row["adaptation_beat_copy"] == 0
    assert "| a | speed-and-step | one speed | 1 | 0 | -0.78 (-) | 0/1 |" in markdown([record])


def test_the_weight_spread_over_single_speed_training() -> None:
    cases = [_record(HumanCaseSpec("WBDS01", t, ("T04",), "a"), {t: 7.0, "T04": 6.0}) for t in ("T05", "T06")]
    cases[1] = dataclasses.replace(cases[1], weights=(0.0, 0.6, 0.8))
    (row,) = weight_spread(cases)
    assert row["speeds"] == ["T05", "T06"] and row["largest_distance"] == pytest.approx(np.linalg.norm([0.6, 0.2, 0.8]))
    assert row["ranges"][0] == [0.0, 0.6]


def test_a_case_in_another_basis_weighs_its_features_and_names_it() -> None:
    case = HumanCaseSpec("WBDS01", "T05", ("T04",), "bilevel", task="speed", basis="energetics")
    assert case.features == ("hip", "knee", "dtau", "work", "collision")
    assert case.key == "bilevel/WBDS01__train-T05__predict-T04__seed0__task-speed__basis-energetics"
    effort = dataclasses.replace(case, basis="effort")
    assert [r.key for r in case.needs()] == [r.key for r in effort.needs()]  # the same reference steps


def test_a_case_in_another_basis_solves_its_estimate_in_its_basis(monkeypatch) -> None:
    """The estimate's steps are solved over the case's basis, the estimate's weights on its features."""
    import ioc_bench.human.case as case_module
    from ioc_bench.weights import parse_weights

    class Stop(Exception):
        pass

    estimate = np.array([0.1, 0.2, 0.3, 0.9, 0.0])
    fitted = type("Outcome", (), {"failed": False, "result": type("R", (), {"weights": estimate})()})()
    seen = {}

    def solve_demo(weights, step, starts, seed, label, model, task, features):
        seen["weights"] = parse_weights(weights, features)
        seen["features"] = features
        raise Stop

    monkeypatch.setattr(case_module, "fit", lambda *args: fitted)
    monkeypatch.setattr(case_module, "solve_demo", solve_demo)
    case = HumanCaseSpec("WBDS01", "T05", ("T04",), "bilevel", task="speed", basis="energetics")
    with pytest.raises(Stop):
        case.run({})
    assert seen["features"] == case.features == ("hip", "knee", "dtau", "work", "collision")
    assert seen["weights"] == pytest.approx(estimate / np.linalg.norm(estimate))


def test_a_record_keeps_its_basis_and_one_without_a_basis_is_the_effort_basis() -> None:
    case = HumanCaseSpec("WBDS01", "T05", ("T04",), "a", basis="energetics")
    record = dataclasses.replace(_record(case, {"T05": 6.0, "T04": 8.0}), weights=(0.6, 0.8, 0.0, 0.0, 0.0))
    again = parse_record(json.loads(json.dumps(record.to_dict())))
    assert again.basis == "energetics" and again.features == case.features
    old = _record(HumanCaseSpec("WBDS01", "T05", ("T04",), "a"), {"T05": 6.0, "T04": 8.0}).to_dict()
    del old["basis"]
    assert parse_record(json.loads(json.dumps(old))).basis == "effort"
    wrong = record.to_dict() | {"features": ["hip", "knee", "dtau"]}
    with pytest.raises(ValueError, match="features"):
        parse_record(json.loads(json.dumps(wrong)))


def test_a_record_keeps_its_provenance_and_one_without_it_has_none_recorded() -> None:
    case = HumanCaseSpec("WBDS01", "T05", ("T04",), "bilevel")
    record = dataclasses.replace(_record(case, {"T05": 6.0, "T04": 8.0}), provenance=provenance())
    assert parse_record(json.loads(json.dumps(record.to_dict()))).provenance == provenance()
    old = record.to_dict()
    del old["provenance"]
    assert parse_record(json.loads(json.dumps(old))).provenance == {}


def test_the_summary_keeps_each_bases_records_apart() -> None:
    effort = _record(HumanCaseSpec("WBDS01", "T05", ("T04",), "a"), {"T05": 7.0, "T04": 6.0})
    energetics = dataclasses.replace(
        _record(HumanCaseSpec("WBDS01", "T05", ("T04",), "a", basis="energetics"), {"T05": 5.0, "T04": 4.0}),
        weights=(0.6, 0.8, 0.0, 0.0, 0.0),
    )
    rows = summarize([energetics, effort])
    assert [(r["algorithm"], r["basis"], r["prediction_rmse_deg"]) for r in rows] == [
        ("a", "effort", 6.0),
        ("a", "energetics", 4.0),
    ]
    table = markdown([effort, energetics])
    assert "| a | speed-and-step | one speed | 7.00 | 6.00 |" in table
    assert "| a (energetics) | speed-and-step | one speed | 5.00 | 4.00 |" in table
