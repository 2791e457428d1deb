"""The compass walker with a torso: a second linkage through the same optimizer code."""

from __future__ import annotations

import numpy as np
import pytest

from ioc_bench import Demonstration, Task, optimize_gait
from ioc_bench.model.compass import COMPASS, compass_linkage


@pytest.fixture(scope="module")
def compass_demo() -> Demonstration:
    return optimize_gait({"hip": 1, "dtau": 1}, task=Task(0.27), starts=2, workers=1, model=COMPASS)


def test_compass_walker_optimises_a_periodic_step(compass_demo):
    d = compass_demo
    assert d.solver.success and d.local_minimum.passed
    assert set(d.features) == {"hip", "dtau", "torso", "steplen", "footheight"}
    link = compass_linkage(d.params)
    tr = d.trajectory
    stance = tr.point(link, "leg_stance", "foot")
    swing = tr.point(link, "leg_swing", "foot")
    assert np.abs(stance).max() < 1e-7  # the stance foot stays pinned at the origin
    step = tr.duration * d.task.speed
    assert swing[-1] == pytest.approx([step, 0.0], abs=1e-7)  # lands one step ahead
    assert swing[1:-1, 1].min() > -1e-7  # never below the ground
    # Periodic: knot 0 is the pre-impact state with the legs swapped, shifted one step back.
    swap = [0, 2, 1]
    assert tr.q[0][swap][:, 1:] == pytest.approx(tr.q[-1][:, 1:], abs=1e-7)
    assert tr.q[0][swap][:, 0] == pytest.approx(tr.q[-1][:, 0] - step, abs=1e-7)


def test_compass_demonstration_round_trips(compass_demo, tmp_path):
    again = Demonstration.load(compass_demo.save(tmp_path / "compass.npz"))
    assert again.model == "compass" and again.features == compass_demo.features
    assert again.gait == compass_demo.gait
