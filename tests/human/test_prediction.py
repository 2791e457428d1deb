"""What a cost predicts of a person's change of gait with speed: on a "person" who walks as
the walker's optimum for known weights, the true weights predict the change and the step
length, and the prediction carried by continuation stays in its family."""

from __future__ import annotations

import dataclasses
import math

import pytest

from ioc_bench.continuation import continue_gait
from ioc_bench.human import load_step
from ioc_bench.human.case import baseline_context, prediction_scores
from ioc_bench.human.observe import leg_angles
from ioc_bench.human.scoring import continue_step, solve_demo
from ioc_bench.model.walker import WALKER
from ioc_bench.task import Task

TRUTH = (1.0, 4.0, 0.0)


@pytest.fixture(scope="module")
def walker_person():
    """WBDS01's T04 and T05 steps replaced by the walker's optimum for :data:`TRUTH` with the
    speed given: the cheapest of one start at T05, carried to T04 (its step length the
    person's, as a measured step length is)."""
    steps = {code: load_step("WBDS01", code) for code in ("T04", "T05")}
    _, demo = solve_demo(TRUTH, steps["T05"], 1, 0, "person", WALKER, Task(steps["T05"].task.speed))
    carried = continue_gait(demo, Task(steps["T04"].task.speed))
    assert demo.solver.success and carried.success
    return {
        code: dataclasses.replace(
            steps[code], angles=leg_angles(d.trajectory), task=Task(steps[code].task.speed, d.gait.step_length)
        )
        for code, d in (("T05", demo), ("T04", carried.demo))
    }


def _scores(weights, steps):
    speed = {code: Task(s.task.speed) for code, s in steps.items()}
    cold, demos = {}, {}
    for code in steps:
        cold[code], demos[code] = solve_demo(weights, steps[code], 1, 0, "estimate", WALKER, speed[code])
    estimate = dict(cold) | {"T04": continue_step(demos["T05"], speed["T04"], "estimate", WALKER)}
    context = baseline_context("WBDS01", [steps["T05"]])
    return prediction_scores("T04", "T05", steps, estimate, cold, context, own=True)


def test_the_true_weights_predict_the_change_and_the_step_length(walker_person) -> None:
    out = _scores(TRUTH, walker_person)
    assert out["continued_from"] == "T05" and out["continuation_solves"] >= 3
    assert out["change_r2"] > 1 - 1e-6 and out["step_length_error"] < 1e-6
    assert out["step_length_change_error"] < 1e-6 and out["family_changed"] is False
    # the model-free baselines are there, from the person's step at T05: not the change itself
    assert out["copy_step_length_error"] > 0 and math.isfinite(out["power_law_step_length_error"])
    assert out["population_rmse_deg"] > 0 and out["population_adaptation_deg"] > 0
    assert "interpolation_rmse_deg" not in out  # one training speed: nothing to interpolate


def test_other_weights_predict_another_change_and_step_length(walker_person) -> None:
    out = _scores((0.0, 0.0, 1.0), walker_person)
    assert out["change_r2"] < 0.9 and out["step_length_error"] > 0.05, out
