"""The benchmark's gait regime: what every demonstration carries, and the task's step length."""

from __future__ import annotations

import pytest

from ioc_bench import Demonstration, Task, optimize_gait
from ioc_bench.trajopt.step_problem import StepRules


def test_demonstration_carries_its_gait_figures_and_local_minimum_check(nominal_demo, tmp_path):
    g, check = nominal_demo.gait, nominal_demo.local_minimum
    assert check is not None and check.passed and check.largest_decrease <= check.tolerance
    assert g.step_length == pytest.approx(nominal_demo.trajectory.duration * nominal_demo.task.speed)
    assert g.cadence == pytest.approx(60 / (g.duration * (0.9 / 9.81) ** 0.5))
    assert set(g.active) == {"physical", "idle", "artificial"} and not g.active["artificial"]
    again = Demonstration.load(nominal_demo.save(tmp_path / "d.npz"))
    assert again.gait == g and again.local_minimum == check


def test_task_step_length_is_held(nominal_demo):
    held = optimize_gait("nominal", task=Task(0.27, step_length=0.5), init=nominal_demo)
    assert held.solver.success
    assert held.trajectory.duration * 0.27 == pytest.approx(0.5, abs=1e-7)
    with pytest.raises(ValueError, match="step_length"):
        Task(0.27, step_length=-1.0)


def test_relaxed_liftoff_lets_the_trailing_foot_leave_upward(nominal_demo):
    """The relaxed lift-off rule (kept for studies) takes no trailing-foot impulse."""
    relaxed = optimize_gait("nominal", init=nominal_demo, rules=StepRules(liftoff="relaxed"), verify=False)
    assert relaxed.solver.success
    assert abs(relaxed.trajectory.trail_impulse).max() == 0.0
    with pytest.raises(ValueError, match="liftoff"):
        StepRules(liftoff="nope")
