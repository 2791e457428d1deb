"""The walker with rolling feet and a free knee: a third linkage through the same optimizer code."""

from __future__ import annotations

import numpy as np
import pytest

from ioc_bench import Demonstration
from ioc_bench.model.feet import footed_linkage
from ioc_bench.model.linkage import ground_gap


@pytest.fixture(scope="module")
def feet_demo(rolling_feet_demo: Demonstration) -> Demonstration:
    return rolling_feet_demo


def test_rolling_feet_walk_a_periodic_step_that_is_a_local_minimum(feet_demo):
    d = feet_demo
    assert d.solver.success and d.local_minimum.passed
    assert set(d.features) == {"hip", "knee", "dtau", "torso", "steplen", "footheight"}
    link = footed_linkage(d.params)
    tr = d.trajectory
    i_st, i_sw = link.index("shank_stance"), link.index("shank_swing")
    stance = np.array([ground_gap(link.segments[i_st], "foot", q[i_st]) for q in tr.q])
    swing = np.array([ground_gap(link.segments[i_sw], "foot", q[i_sw]) for q in tr.q])
    assert np.abs(stance).max() < 1e-7  # the stance arc rolls: its anchor stays at the origin, its bottom on the ground
    rolled = d.params.roll_radius * np.ptp(tr.q[:, i_st, 2])
    assert rolled > 0.05  # the contact point travels along the arc
    step = tr.duration * d.task.speed
    assert swing[-1] == pytest.approx([step, 0.0], abs=1e-7)  # lands one step ahead
    assert swing[1:-1, 1].min() > -1e-7  # the swing arc never dips below the ground


def test_a_free_knee_stays_in_its_range_without_a_lock(feet_demo):
    link = footed_linkage(feet_demo.params)
    assert not link.locked
    theta = feet_demo.trajectory.q[:, :, 2]
    for role in ("stance", "swing"):
        knee = theta[:, link.index(f"shank_{role}")] - theta[:, link.index(f"thigh_{role}")]
        assert knee.min() > -1e-7 and knee.max() < feet_demo.params.knee_max_flexion


def test_rolling_feet_demonstration_round_trips(feet_demo, tmp_path):
    again = Demonstration.load(feet_demo.save(tmp_path / "feet.npz"))
    assert again.model == "rolling-feet" and again.params == feet_demo.params
    assert again.features == feet_demo.features
