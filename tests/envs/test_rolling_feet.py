"""The rolling-feet walker in MuJoCo: its demonstration passes every physical check, a wrong
one fails the check naming what is wrong, and the environment stands and rolls on the arcs."""

from __future__ import annotations

from dataclasses import replace

import mujoco
import numpy as np
import pytest

from envs.checks import (
    REPLAYABLE_MODELS,
    check_replayable,
    inverse_dynamics_check,
    open_loop_replay,
    physics_checks,
    replay,
    stance_ground_forces,
)
from envs.physics import build_model, foot_contact_point, foot_roll
from envs.planar_walker import PlanarWalkerEnv
from envs.reference import DemoReference
from ioc_bench import Demonstration
from ioc_bench.model.feet import ROLLING_FEET, FootedParams


@pytest.fixture(scope="module")
def demo(rolling_feet_demo: Demonstration) -> Demonstration:
    assert rolling_feet_demo.model == ROLLING_FEET.name
    assert rolling_feet_demo.solver.success, rolling_feet_demo.solver
    return rolling_feet_demo


@pytest.fixture(scope="module")
def checks(demo: Demonstration):
    return {c.name: c for c in physics_checks(demo, inverse_dynamics_check(demo))}


def _scaled_torques(demo: Demonstration, factor: float) -> Demonstration:
    return replace(demo, trajectory=replace(demo.trajectory, tau=demo.trajectory.tau * factor))


def test_the_rolling_feet_model_is_replayable(demo: Demonstration):
    assert ROLLING_FEET.name in REPLAYABLE_MODELS
    check_replayable(demo)


def test_the_rolling_feet_demonstration_passes_every_physical_check(checks):
    for c in checks.values():
        assert c.passed, c
    assert checks["inverse_dynamics"].value < 1e-9  # MuJoCo's dynamics are the optimizer's
    assert checks["ground_normal_force"].value > 0.5  # body weights: well loaded throughout


def test_the_ground_force_is_the_optimizers_pin_force(demo: Demonstration):
    """Newton's law for the whole body in MuJoCo gives the optimizer's ground pin force."""
    link = DemoReference.of(demo).linkage
    pin = demo.trajectory.pin_forces[:, link.pin_index(ROLLING_FEET.roles.contact_pin)]
    assert stance_ground_forces(demo) == pytest.approx(pin, abs=1e-9)


def test_scaled_torques_fail_the_inverse_dynamics_check_only(demo: Demonstration):
    wrong = _scaled_torques(demo, 1.2)
    result = inverse_dynamics_check(wrong)
    # The residual is the 0.2 excess of the 1.2-times peak torque.
    assert result.relative_residual == pytest.approx(0.2 / 1.2, rel=1e-6)
    failed = {c.name for c in physics_checks(wrong, result) if not c.passed}
    assert failed == {"inverse_dynamics"}


@pytest.mark.parametrize("radius", [0.29, 1e-4], ids=["radius-0.29", "point-foot"])
def test_a_foot_of_another_radius_fails_the_inverse_dynamics_check(demo: Demonstration, radius: float):
    """The check sees where the ground force acts: a MuJoCo foot of another radius (down to
    a point foot at the shank's end) needs other torques for the same motion."""
    result = inverse_dynamics_check(demo, replace(demo.params, roll_radius=radius))
    assert not result.passed
    assert result.relative_residual > 0.01


def test_the_contact_point_and_foot_radius_come_from_the_linkage(demo: Demonstration):
    """The environment starts on the demonstration's rolling contact: the stance sphere
    touches the floor at its lowest point, ``R theta`` ahead of the arc's anchor (the origin)."""
    radius = foot_roll(demo.params)
    assert radius == demo.params.roll_radius
    env = PlanarWalkerEnv(params=demo.params, demonstration=demo)
    env.reset()
    link, q0 = DemoReference.of(demo).linkage, demo.trajectory.q[0]
    theta = q0[link.index("shank_stance"), 2]
    contact = foot_contact_point(env.model, env.data, "a", radius)
    assert contact == pytest.approx([radius * theta, 0.0, 0.0], abs=1e-12)
    env.close()


def test_a_standing_start_stands_on_the_lowest_sphere():
    env = PlanarWalkerEnv(params=FootedParams())
    env.reset(seed=0)
    radius = foot_roll(FootedParams())
    lowest = min(foot_contact_point(env.model, env.data, leg, radius)[2] for leg in "ab")
    assert lowest == pytest.approx(0.0, abs=1e-12)
    assert env.data.qpos[1] == pytest.approx(FootedParams().leg_length, abs=0.01)
    env.close()


def test_the_stance_sphere_rolls_without_slipping(demo: Demonstration):
    """Open loop, up to the landing: the stance sphere's anchor (contact point minus ``R
    theta``) stays put while the contact point moves ``R`` per radian (measured 2.5e-5 L)."""
    result = open_loop_replay(demo)
    model = build_model(demo.params)
    data = mujoco.MjData(model)
    radius = foot_roll(demo.params)
    end = np.searchsorted(result.times, result.touchdown_time or result.times[-1])
    anchors, contacts = [], []
    for qpos in result.qpos[:end]:
        data.qpos[:] = qpos
        mujoco.mj_kinematics(model, data)
        contacts.append(foot_contact_point(model, data, "a", radius)[0])
        anchors.append(contacts[-1] - radius * (qpos[2] + qpos[3] + qpos[4]))  # shank angle
    assert np.ptp(contacts) > 0.05  # the contact point travels along the ground
    assert np.ptp(anchors) < 2e-4


def test_the_replay_walks_and_passes(demo: Demonstration):
    report = replay(demo, steps=2)
    assert report.passed, report.failures
    assert report.replay_error is None
    assert report.closed_loop.steps_walked == 2
    assert report.closed_loop.stance_contact > 0.99


def test_a_rolling_feet_environment_refuses_a_walker_demonstration(nominal_demo: Demonstration):
    env = PlanarWalkerEnv(params=FootedParams())
    with pytest.raises(ValueError, match="'walker' model"):
        env.reset(options={"demonstration": nominal_demo})
    env.close()
