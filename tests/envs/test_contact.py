"""v2's contact: friction on the stance foot only, and heel strikes that are landings, not grazes."""

from __future__ import annotations

import numpy as np
import pytest

from envs.coordinates import motor_controls
from envs.heel_strikes import LANDING_FRACTION, StanceTracker, landing_distance, step_length
from envs.physics import STANCE_CONDIM, SWING_CONDIM, foot_geoms
from envs.planar_walker import PlanarWalkerEnv
from envs.reference import DemoReference
from ioc_bench import Demonstration
from ioc_bench.model.walker import WALKER_ROLES, walker_linkage


def _condims(env: PlanarWalkerEnv) -> dict[str, int]:
    return {leg: int(env.model.geom_condim[gid]) for leg, gid in foot_geoms(env.model).items()}


def _swing_foot_heights(demo: Demonstration) -> np.ndarray:
    return demo.trajectory.point(walker_linkage(demo.params), *WALKER_ROLES.swing_foot)[:, 1]


def test_only_the_stance_foot_has_friction_and_the_feet_decide():
    env = PlanarWalkerEnv()
    _, info = env.reset(seed=0)
    stance = info["stance_leg"]
    assert _condims(env) == {leg: STANCE_CONDIM if leg == stance else SWING_CONDIM for leg in "ab"}
    floor = env.model.geom("floor").id
    assert all(env.model.geom_priority[g] > env.model.geom_priority[floor] for g in foot_geoms(env.model).values())


def test_a_mid_swing_graze_is_frictionless_and_no_heel_strike(nominal_demo: Demonstration):
    """The nominal step's swing foot touches the ground mid-swing (height 0 at one knot, half a step ahead)."""
    z = _swing_foot_heights(nominal_demo)
    graze = 1 + int(np.argmin(z[1:-1]))
    assert z[graze] < 1e-6 and 0 < graze < nominal_demo.trajectory.n_knots - 1
    env = PlanarWalkerEnv(demonstration=nominal_demo, frame_skip=1)
    env.reset()
    ref, tr = DemoReference.of(nominal_demo), nominal_demo.trajectory
    # From the demonstration's state a knot before the graze, the swing foot in the air.
    env.set_state(ref.qpos[graze - 1], ref.qvel[graze - 1])
    touched = False
    for t in np.arange(tr.times[graze - 1], tr.times[graze + 1], env.dt):
        info = env.step(motor_controls(ref.torque(t), "a").astype(np.float32))[4]
        if not touched:
            assert env.get_state().swing_lifted  # so only the landing distance rules the graze out
        for i in range(env.data.ncon):
            contact = env.data.contact[i]
            if foot_geoms(env.model)["b"] in contact.geom:
                touched = True
                assert contact.dim == SWING_CONDIM  # the floor holds the swing foot up, never drags it
        assert info["heel_strikes"] == 0 and info["stance_leg"] == "a"
    assert touched


def test_friction_follows_the_roles_at_a_heel_strike(nominal_demo: Demonstration):
    from envs.tracking import TrackingPolicy

    env, policy = PlanarWalkerEnv(demonstration=nominal_demo), TrackingPolicy(nominal_demo)
    obs, info = env.reset()
    assert _condims(env) == {"a": STANCE_CONDIM, "b": SWING_CONDIM}
    while info["heel_strikes"] < 1:
        obs, _, terminated, _, info = env.step(policy(obs, info))
        assert not terminated
    assert info["stance_leg"] == "b"
    assert _condims(env) == {"a": SWING_CONDIM, "b": STANCE_CONDIM}
    # The landing was beyond the landing zone's edge, ahead of the new swing (old stance) foot.
    feet = {leg: env.data.site_xpos[env.model.site(f"foot_{leg}").id][0] for leg in "ab"}
    assert feet["b"] - feet["a"] > landing_distance(nominal_demo)


def test_the_landing_distance_is_three_quarters_of_the_demonstrated_step(nominal_demo: Demonstration):
    length = step_length(nominal_demo)
    assert length == pytest.approx(nominal_demo.gait.step_length, rel=1e-6)
    assert landing_distance(nominal_demo) == pytest.approx(LANDING_FRACTION * length)
    assert landing_distance(None) == 0.0
    env = PlanarWalkerEnv(demonstration=nominal_demo)
    env.reset()
    assert env.get_state().landing_distance == pytest.approx(LANDING_FRACTION * length)
    env.reset(options={"demonstration": None}, seed=0)
    assert env.get_state().landing_distance == 0.0
    # The demonstration's own mid-swing touchdowns lie short of it.
    link = walker_linkage(nominal_demo.params)
    swing = nominal_demo.trajectory.point(link, *WALKER_ROLES.swing_foot)
    stance = nominal_demo.trajectory.point(link, *WALKER_ROLES.stance_foot)
    touching = np.flatnonzero(swing[1:-1, 1] < 1e-6) + 1
    assert touching.size and np.all(swing[touching, 0] - stance[touching, 0] < landing_distance(nominal_demo))


def test_a_touchdown_short_of_the_landing_distance_is_a_graze():
    tracker = StanceTracker("a", landing_distance=0.3)
    both, lifted = {"a": True, "b": True}, {"a": True, "b": False}
    assert not tracker.update(lifted, {"a": 0.0, "b": -0.2})  # lift-off behind
    assert not tracker.update(both, {"a": 0.0, "b": 0.18})  # mid-swing graze ahead: no heel strike
    assert tracker.stance_leg == "a" and tracker.heel_strikes == 0
    assert not tracker.update(lifted, {"a": 0.0, "b": 0.25})
    assert tracker.update(both, {"a": 0.0, "b": 0.34})  # the landing
    assert (tracker.stance_leg, tracker.heel_strikes) == ("b", 1)
    with pytest.raises(ValueError, match="landing_distance"):
        StanceTracker("a", landing_distance=-0.1)
