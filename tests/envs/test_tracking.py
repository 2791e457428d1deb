"""``TrackingPolicy``: a demonstration walks through ``env.step``, alone and in a vector env."""

from __future__ import annotations

import gymnasium as gym
import numpy as np
import pytest

from envs.coordinates import motor_controls
from envs.heel_strikes import StanceTracker
from envs.planar_walker import PlanarWalkerEnv
from envs.reference import DemoReference
from envs.tracking import PDGains, TrackingPolicy
from ioc_bench import Demonstration

ENV_ID = "envs:IOCBench/PlanarWalker-v2"


def _walk(env: PlanarWalkerEnv, policy: TrackingPolicy, steps: int, limit: int = 5000) -> tuple[list[float], dict]:
    """Heel-strike times of a walk of ``steps`` steps, and the last info."""
    obs, info = env.reset()
    strikes: list[float] = []
    for i in range(limit):
        obs, _, terminated, truncated, info = env.step(policy(obs, info))
        assert not (terminated or truncated), f"fell after {len(strikes)} steps"
        if info["heel_strikes"] > len(strikes):
            strikes.append((i + 1) * env.dt)
        if len(strikes) == steps:
            return strikes, info
    raise AssertionError(f"only {len(strikes)} steps in {limit} env steps")


def test_policy_walks_ten_steps_in_the_default_environment(nominal_demo: Demonstration):
    """The user's loop at the env's own dt = 0.01: ten heel strikes at the demonstration's pace.

    With decisions only every 0.01 the walk may limp (the earlier short steps alternated
    by up to ~15 %, 0.85-1.05 for a 0.895 step; the current nominal step measured
    1.32-1.33 for 1.29; docs/notes/2026-11-25-env-physics-step-and-rates.md, "Control rate", and
    docs/notes/2026-11-25-grazing-swing-feet.md), so the pace is judged over the ten steps,
    not step by step (the replay check does that at finer control).
    """
    env = PlanarWalkerEnv(demonstration=nominal_demo)
    strikes, info = _walk(env, TrackingPolicy(nominal_demo), steps=10)
    assert np.mean(np.diff([0.0, *strikes])) == pytest.approx(nominal_demo.trajectory.duration, rel=0.05)
    speed = (info["x_position"] - DemoReference.of(nominal_demo).qpos[0, 0]) / strikes[-1]
    assert speed == pytest.approx(nominal_demo.task.speed, rel=0.05)
    assert info["stance_leg"] == "a"  # ten swaps: back on leg a


def test_policy_at_the_initial_state_is_the_demonstrations_torque(nominal_demo: Demonstration):
    """On the demonstration's own knot 0, the feedback vanishes: the action is the first knot's torque."""
    env = PlanarWalkerEnv(demonstration=nominal_demo)
    obs, info = env.reset()
    cmd = TrackingPolicy(nominal_demo).command(obs, info)
    assert cmd.phase == pytest.approx(0.0, abs=1e-9)
    assert cmd.joints == pytest.approx(cmd.joints_ref, abs=1e-12)
    assert np.abs(cmd.tau_fb).max() < 1e-6
    assert cmd.action == pytest.approx(nominal_demo.trajectory.tau[0], abs=1e-6)
    # With leg b in the stance role (mid-step, so the policy keeps it) the torques go to the
    # other motors. (At knot 0 the hip is exactly as far ahead of the trailing foot as at the
    # step's end, so which role that foot gets there is a tie.)
    from envs.coordinates import to_generalized
    from ioc_bench.model.walker import walker_linkage

    tr, k = nominal_demo.trajectory, nominal_demo.trajectory.n_knots // 2
    env.set_state(*to_generalized(walker_linkage(nominal_demo.params), tr.q[k], tr.v[k], None, "b")[:2])
    swapped = TrackingPolicy(nominal_demo).command(env._get_obs(), {"stance_leg": "b"})
    assert swapped.stance_leg == "b"
    assert swapped.action == pytest.approx(motor_controls(swapped.tau_ff + swapped.tau_fb, "b"))
    assert not np.allclose(swapped.action, motor_controls(swapped.tau_ff + swapped.tau_fb, "a"))


def test_policy_tracks_the_next_step_once_the_hip_passes_the_steps_end(nominal_demo: Demonstration):
    """The demonstration's next step (legs swapped) begins where its step ends, touched down or not."""
    from envs.coordinates import to_generalized
    from ioc_bench.model.walker import walker_linkage

    tr, policy = nominal_demo.trajectory, TrackingPolicy(nominal_demo)
    env = PlanarWalkerEnv(demonstration=nominal_demo)
    env.reset()
    link = walker_linkage(nominal_demo.params)
    # The next step's second knot (leg b in stance), before the environment saw a heel strike.
    env.set_state(*to_generalized(link, tr.q[1], tr.v[1], None, "b")[:2])
    obs = env._get_obs()
    early = policy.command(obs, {"stance_leg": "a"})
    assert early.stance_leg == "b"
    assert early.phase == pytest.approx(tr.times[1], abs=1e-6)
    assert np.array_equal(early.action, policy.command(obs, {"stance_leg": "b"}).action)
    # Within the step the environment's stance leg is kept.
    env.set_state(*to_generalized(link, tr.q[-2], tr.v[-2], None, "a")[:2])
    late = policy.command(env._get_obs(), {"stance_leg": "a"})
    assert late.stance_leg == "a" and late.phase == pytest.approx(tr.times[-2], abs=1e-6)


def test_policy_serves_a_vector_env_like_single_envs(nominal_demo: Demonstration):
    policy = TrackingPolicy(nominal_demo)
    vec = gym.make_vec(ENV_ID, num_envs=3, vectorization_mode="sync", demonstration=nominal_demo)
    single = PlanarWalkerEnv(demonstration=nominal_demo)
    obs, info = vec.reset(seed=0)
    s_obs, s_info = single.reset()
    for _ in range(120):
        action = policy(obs, info)
        assert action.shape == (3, 4) and action.dtype == np.float32
        s_action = policy(s_obs, s_info)
        assert np.array_equal(action[1], s_action)
        obs, _, terminated, _, info = vec.step(action)
        s_obs, *_, s_info = single.step(s_action)
        assert not terminated.any()
    assert np.array_equal(obs[2], s_obs)
    assert list(info["heel_strikes"]) == [s_info["heel_strikes"]] * 3
    vec.close()


def test_policy_needs_the_environments_info(nominal_demo: Demonstration):
    policy = TrackingPolicy(nominal_demo)
    obs, _ = PlanarWalkerEnv(demonstration=nominal_demo).reset()
    with pytest.raises(ValueError, match="stance_leg"):
        policy(obs, {})
    with pytest.raises(ValueError, match="stance leg"):
        policy(obs, {"stance_leg": "left"})
    with pytest.raises(ValueError, match="17 or 18"):
        policy(obs[:13], {"stance_leg": "a"})
    with pytest.raises(ValueError, match="n observations"):
        policy(np.stack([obs, obs]), {"stance_leg": np.array(["a"], dtype=object)})
    with pytest.raises(ValueError, match="kp"):
        PDGains(kp=-1.0)


def test_policy_loads_a_file(nominal_demo: Demonstration, tmp_path):
    path = nominal_demo.save(tmp_path / "demo.npz")
    obs, info = PlanarWalkerEnv(demonstration=path).reset()
    assert np.array_equal(TrackingPolicy(path)(obs, info), TrackingPolicy(nominal_demo)(obs, info))


def test_heel_strike_needs_a_lift_off_and_a_landing_ahead():
    tracker = StanceTracker("a")
    both, ahead, behind = {"a": True, "b": True}, {"a": 0.0, "b": 0.3}, {"a": 0.0, "b": -0.3}
    assert not tracker.update(both, ahead)  # b never left the floor: not a step
    assert not tracker.update({"a": True, "b": False}, behind)  # lift-off
    assert tracker.swing_lifted
    assert not tracker.update(both, behind)  # a scuff behind the stance foot
    assert tracker.update(both, ahead)  # landing ahead: heel strike
    assert (tracker.stance_leg, tracker.heel_strikes, tracker.swing_lifted) == ("b", 1, False)
    assert not tracker.update(both, {"a": 0.6, "b": 0.3})  # a has not lifted off yet
    with pytest.raises(ValueError, match="stance leg"):
        StanceTracker("c")
