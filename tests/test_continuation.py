"""Continuation: an optimum carried to another speed, warm, in steps, stays a verified optimum
of the same family, and refuses what it cannot carry."""

from __future__ import annotations

import numpy as np
import pytest

from ioc_bench.continuation import SPEED_STEP, continue_gait
from ioc_bench.human.observe import leg_angles
from ioc_bench.human.scoring import knee_at_strike_deg
from ioc_bench.optimize import optimize_gait
from ioc_bench.task import Task


@pytest.fixture(scope="module")
def start():
    demo = optimize_gait("nominal", task=Task(0.27), starts=1, seed=0, workers=1, verify=False, n_intervals=20)
    assert demo.solver.success
    return demo


def test_a_step_carried_to_another_speed_is_a_verified_optimum_there(start) -> None:
    end = continue_gait(start, Task(0.33))
    assert end.success and end.reached == 1.0 and end.demo.task.speed == 0.33
    assert end.solves >= int(np.ceil((0.33 - 0.27) / SPEED_STEP))
    assert end.demo.local_minimum is not None and end.demo.local_minimum.passed
    # the same family: the stance knee at heel strike moves little, the step lengthens with speed
    knee = [knee_at_strike_deg(leg_angles(d.trajectory)) for d in (start, end.demo)]
    assert abs(knee[1] - knee[0]) < 5.0, knee
    assert end.demo.gait.step_length > start.gait.step_length


def test_carried_back_it_returns_to_the_optimum_it_left(start) -> None:
    there = continue_gait(start, Task(0.31), verify=False)
    back = continue_gait(there.demo, Task(0.27), verify=False)
    assert back.success
    assert np.max(np.abs(back.demo.trajectory.q - start.trajectory.q)) < 1e-3
    assert back.demo.solver.objective == pytest.approx(start.solver.objective, rel=1e-4)


def test_a_step_of_given_length_is_carried_in_speed_and_length_together() -> None:
    fixed = optimize_gait("nominal", task=Task(0.27, 0.45), starts=1, seed=0, workers=1, verify=False, n_intervals=20)
    end = continue_gait(fixed, Task(0.31, 0.5), verify=False)
    assert fixed.solver.success and end.success
    assert end.demo.task == Task(0.31, 0.5) and end.demo.gait.step_length == pytest.approx(0.5, rel=1e-6)


def test_what_it_cannot_carry_is_refused(start) -> None:
    with pytest.raises(ValueError, match="fix the step length"):
        continue_gait(start, Task(0.3, step_length=0.5))
    with pytest.raises(ValueError, match="speed_step"):
        continue_gait(start, Task(0.3), speed_step=0.0)
    with pytest.raises(ValueError, match="successful Demonstration"):
        continue_gait("demo.npz", Task(0.3))
