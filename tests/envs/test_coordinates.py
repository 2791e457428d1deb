"""Segment states <-> MuJoCo coordinates: the two descriptions place every point alike."""

from __future__ import annotations

import mujoco
import numpy as np
import pytest

from envs.coordinates import (
    actuated_dofs,
    generalized_torques,
    motor_controls,
    other_leg,
    role_torques,
    to_generalized,
    to_segments,
)
from envs.physics import build_model
from ioc_bench import Demonstration
from ioc_bench.model.linkage import point_position
from ioc_bench.model.walker import walker_linkage


@pytest.mark.parametrize("stance", ["a", "b"])
def test_round_trip_at_every_knot(nominal_demo: Demonstration, stance: str):
    link = walker_linkage(nominal_demo.params)
    tr = nominal_demo.trajectory
    # The demonstration's centres of mass satisfy the joint constraints only to the solver's
    # feasibility; the round trip rebuilds them from the angles, so it can differ by that much.
    tol = 1e-12 + nominal_demo.solver.max_violation
    for k in range(tr.n_knots):
        qpos, qvel, qacc = to_generalized(link, tr.q[k], tr.v[k], tr.acc[k], stance)
        q, v = to_segments(link, qpos, qvel, stance)
        assert q == pytest.approx(tr.q[k], abs=tol)
        assert v == pytest.approx(tr.v[k], abs=tol)
        assert np.all(np.isfinite(qacc))


@pytest.mark.parametrize("stance", ["a", "b"])
def test_mujoco_places_points_like_the_linkage(nominal_demo: Demonstration, stance: str):
    link = walker_linkage(nominal_demo.params)
    model = build_model(nominal_demo.params)
    data = mujoco.MjData(model)
    tr = nominal_demo.trajectory
    swing = other_leg(stance)
    for k in (0, tr.n_knots // 2, tr.n_knots - 1):
        data.qpos[:], data.qvel[:], _ = to_generalized(link, tr.q[k], tr.v[k], None, stance)
        mujoco.mj_kinematics(model, data)
        for leg, role in ((stance, "stance"), (swing, "swing")):
            i_shank = link.index(f"shank_{role}")
            foot = point_position(link.segments[i_shank], "foot", tr.q[k][i_shank])
            knee = point_position(link.segments[i_shank], "knee", tr.q[k][i_shank])
            assert data.site(f"foot_{leg}").xpos[[0, 2]] == pytest.approx(foot, abs=1e-12)
            assert data.body(f"shank_{leg}").xpos[[0, 2]] == pytest.approx(knee, abs=1e-12)
            # Centres of mass agree too (MuJoCo's xipos).
            assert data.body(f"shank_{leg}").xipos[[0, 2]] == pytest.approx(tr.q[k][i_shank][:2], abs=1e-12)
    # The stance foot is at the origin throughout the step.
    assert tr.point(link, "shank_stance", "foot") == pytest.approx(np.zeros((tr.n_knots, 2)), abs=1e-6)


def test_torque_mappings():
    role = np.array([0.1, 0.2, 0.3, 0.4])  # hip stance, hip swing, knee stance, knee swing
    assert motor_controls(role, "a") == pytest.approx(role)
    assert motor_controls(role, "b") == pytest.approx([0.2, 0.1, 0.4, 0.3])  # hip_a, hip_b, knee_a, knee_b
    for stance in "ab":
        assert role_torques(motor_controls(role, stance), stance) == pytest.approx(role)
        gen = generalized_torques(role, stance)
        assert gen[:3] == pytest.approx(0.0)
        assert gen[actuated_dofs(stance)] == pytest.approx(role)
    assert generalized_torques(role, "b")[[3, 4, 5, 6]] == pytest.approx([0.2, 0.4, 0.1, 0.3])


def test_bad_leg_names_are_rejected():
    with pytest.raises(ValueError, match="stance leg"):
        actuated_dofs("left")
