"""The state API (v1 on), lossless observations, action checks, reward weights and the renderer choice."""

from __future__ import annotations

import copy
import pickle
from dataclasses import replace

import numpy as np
import pytest

from envs.observation import observation_names, split_observation
from envs.planar_walker import PlanarWalkerEnv
from envs.state import WalkerState
from ioc_bench import Demonstration
from ioc_bench.weights import parse_weights


def _stepped(env: PlanarWalkerEnv, n: int, seed: int = 0) -> PlanarWalkerEnv:
    rng = np.random.default_rng(seed)
    for _ in range(n):
        env.step(rng.uniform(-0.05, 0.05, size=4).astype(np.float32))
    return env


def _same_step(a: tuple, b: tuple) -> None:
    """Two ``step`` results are identical, bit for bit."""
    (obs_a, r_a, te_a, tr_a, info_a), (obs_b, r_b, te_b, tr_b, info_b) = a, b
    assert np.array_equal(obs_a, obs_b)
    assert r_a == r_b and te_a == te_b and tr_a == tr_b
    assert info_a.keys() == info_b.keys()
    for key in info_a:
        assert info_a[key] == info_b[key], key


def test_observation_layout_names_every_entry():
    env = PlanarWalkerEnv()
    obs, _ = env.reset(seed=0)
    assert obs.shape == env.observation_space.shape == (len(observation_names()),) == (17,)
    assert np.all(np.isinf(env.observation_space.low)) and np.all(np.isinf(env.observation_space.high))
    with_x = PlanarWalkerEnv(exclude_current_positions_from_observation=False)
    assert with_x.reset(seed=0)[0].shape == (18,)
    assert observation_names(False)[0] == "qpos_rootx"
    with pytest.raises(ValueError, match="17 or 18"):
        split_observation(np.zeros(13))


def test_observations_are_not_clipped():
    """Fast joints and a hip past pi read as they are (v0 clipped them at 10 and pi)."""
    env = PlanarWalkerEnv(exclude_current_positions_from_observation=False)
    env.reset(seed=0)
    qpos = env.init_qpos.copy()
    qpos[3] = 4.0  # hip of leg a turned past pi
    qvel = np.array([0.5, -0.2, 12.0, -26.7, 30.0, 0.0, 11.0])
    env.set_state(qpos, qvel)
    state = split_observation(env._get_obs())
    assert state.x == qpos[0]
    assert np.array_equal(state.positions, qpos[1:])
    assert np.array_equal(state.qvel, qvel)
    assert env.observation_space.contains(env._get_obs())


def test_previous_torque_is_observed_as_applied():
    env = PlanarWalkerEnv()
    obs, _ = env.reset(seed=0)
    assert np.array_equal(split_observation(obs).previous_torque, np.zeros(4))
    action = np.array([0.1, -0.2, 3.0, -0.05], dtype=np.float32)  # 3.0 is clipped to the bound 1
    obs, *_ = env.step(action)
    applied = action.astype(float)
    applied[2] = 1.0
    assert np.array_equal(split_observation(obs).previous_torque, applied)
    # The dtau term of the next step is computed from exactly that torque (in the paper's
    # units, N m and s for a 1 m, 1 kg walker: 0.001 sum (dtau / dt)^2 dt scales by g^2.5).
    info = env.step(np.zeros(4, dtype=np.float32))[4]
    prev = split_observation(obs).previous_torque
    g = 9.81
    assert info["phi_dtau"] == pytest.approx(g**2.5 * 0.001 * np.sum((prev / env.dt) ** 2) * env.dt, rel=1e-12)


@pytest.mark.parametrize("bad", [np.nan, np.inf, -np.inf])
def test_non_finite_actions_are_rejected(bad):
    env = PlanarWalkerEnv()
    env.reset(seed=0)
    before = env.get_state()
    with pytest.raises(ValueError, match="finite"):
        env.step(np.array([0.0, bad, 0.0, 0.0], dtype=np.float32))
    assert np.array_equal(env.get_state().physics, before.physics)  # nothing was simulated


def test_actions_of_the_wrong_shape_are_rejected():
    env = PlanarWalkerEnv()
    env.reset(seed=0)
    with pytest.raises(ValueError, match=r"shape \(4,\)"):
        env.step(np.zeros(3, dtype=np.float32))


def test_state_round_trip_then_step_equals_step():
    env = _stepped(PlanarWalkerEnv(), 25)
    action = np.array([0.03, -0.02, 0.01, 0.04], dtype=np.float32)
    snapshot = env.get_state()
    first = env.step(action)
    env.set_state(snapshot)
    _same_step(first, env.step(action))
    # Into another environment, never reset.
    other = PlanarWalkerEnv()
    other.set_state(snapshot)
    _same_step(first, other.step(action))


def test_state_round_trip_keeps_the_gait_bookkeeping(nominal_demo: Demonstration):
    from envs.tracking import TrackingPolicy

    env, policy = PlanarWalkerEnv(demonstration=nominal_demo), TrackingPolicy(nominal_demo)
    obs, info = env.reset()
    while info["heel_strikes"] < 1:
        obs, _, terminated, _, info = env.step(policy(obs, info))
        assert not terminated
    snapshot = env.get_state()
    assert snapshot.stance_leg == "b" and snapshot.heel_strikes == 1
    assert snapshot.landing_distance > 0  # from the demonstration's step length
    action = policy(obs, info)
    first = env.step(action)
    fresh = PlanarWalkerEnv()  # a standing start: landing distance 0, leg a's foot with friction
    fresh.set_state(snapshot)
    assert fresh.get_state().landing_distance == snapshot.landing_distance
    assert np.array_equal(fresh.model.geom_condim, env.model.geom_condim)  # leg b's foot has the friction now
    _same_step(first, fresh.step(action))


def test_snapshot_is_read_only_and_checked():
    env = _stepped(PlanarWalkerEnv(), 3)
    snapshot = env.get_state()
    assert np.array_equal(snapshot.qpos, env.data.qpos) and np.array_equal(snapshot.qvel, env.data.qvel)
    assert snapshot.time == env.data.time
    with pytest.raises(ValueError):
        snapshot.physics[0] = 1.0
    with pytest.raises(ValueError, match="physics"):
        WalkerState(np.zeros(3), None, "a", False, 0, np.ones(3))
    with pytest.raises(ValueError, match="stance leg"):
        WalkerState(snapshot.physics, None, "c", False, 0, np.ones(3))
    with pytest.raises(ValueError, match="WalkerState"):
        env.set_state(np.zeros(7))
    with pytest.raises(ValueError, match="shapes"):
        env.set_state(np.zeros(6), np.zeros(7))


def test_gymnasium_style_state_accessors():
    env = PlanarWalkerEnv()
    env.reset(seed=0)
    assert np.array_equal(env.state_vector(), np.concatenate([env.data.qpos, env.data.qvel]))
    assert env.init_qpos[1] == pytest.approx(env.params.leg_length)
    env.set_state(env.init_qpos, env.init_qvel)
    assert np.array_equal(env.state_vector(), np.concatenate([env.init_qpos, env.init_qvel]))


@pytest.mark.parametrize("clone", [copy.deepcopy, lambda e: pickle.loads(pickle.dumps(e))])
def test_deepcopy_and_pickle_continue_the_episode(clone):
    env = _stepped(PlanarWalkerEnv(weights="penalize-hip"), 10)
    env.reset(seed=5)
    _stepped(env, 10)
    twin = clone(env)
    action = np.array([0.02, 0.01, -0.03, 0.0], dtype=np.float32)
    _same_step(env.step(action), twin.step(action))
    # The random generator travels too: the next noisy start is the same.
    assert np.array_equal(env.reset()[0], twin.reset()[0])


def test_weights_follow_the_demonstration_unless_given(nominal_demo: Demonstration):
    knee = replace(nominal_demo, weights={"hip": 1.0, "knee": 10.0, "dtau": 1.0})
    env = PlanarWalkerEnv()
    assert env.weights == pytest.approx(parse_weights("nominal"))
    _, info = env.reset(options={"demonstration": knee})
    assert env.weights == pytest.approx(parse_weights("penalize-knee"))
    assert info["reward_weights"] == pytest.approx(parse_weights("penalize-knee"))
    env.reset(seed=0)  # a standing start: nominal again
    assert env.weights == pytest.approx(parse_weights("nominal"))
    fixed = PlanarWalkerEnv(weights="penalize-hip")
    fixed.reset(options={"demonstration": knee})
    assert fixed.weights == pytest.approx(parse_weights("penalize-hip"))
    # The reward uses the episode's weights.
    info = env.reset(options={"demonstration": knee})[1] | env.step(np.full(4, 0.1, dtype=np.float32))[4]
    assert info["reward_knee"] == pytest.approx(-parse_weights("penalize-knee")[1] * info["phi_knee"])


def test_demonstration_argument_starts_every_episode(nominal_demo: Demonstration):
    env = PlanarWalkerEnv(demonstration=nominal_demo)
    first, info = env.reset(seed=0)
    second, _ = env.reset(seed=1)  # seeds do not matter: no noise
    assert np.array_equal(first, second) and info["stance_leg"] == "a"
    standing, info = env.reset(seed=0, options={"demonstration": None})
    assert not np.array_equal(first, standing)
    assert info["stance_leg"] in ("a", "b")
    assert np.array_equal(env.reset()[0], first)


def test_explicit_mujoco_renderer_never_falls_back(monkeypatch):
    """Once ``auto`` fell back to the stick figure, ``renderer="mujoco"`` still raises."""
    import envs.rendering as rendering

    def no_context(*args, **kwargs):
        raise RuntimeError("no OpenGL\ncontext")

    monkeypatch.setattr(rendering.mujoco, "Renderer", no_context)
    monkeypatch.setattr(rendering, "_GL_FAILURE", None)
    auto = PlanarWalkerEnv(render_mode="rgb_array", renderer="auto", width=32, height=24)
    auto.reset(seed=0)
    assert auto.render().shape == (24, 32, 3)
    assert auto.renderer_in_use == "stick"
    explicit = PlanarWalkerEnv(render_mode="rgb_array", renderer="mujoco", width=32, height=24)
    explicit.reset(seed=0)
    with pytest.raises(rendering.RendererUnavailableError, match="no OpenGL context"):
        explicit.render()
    assert explicit.renderer_in_use is None


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({"frame_skip": 0}, "frame_skip"),
        ({"frame_skip": 2.5}, "frame_skip"),
        ({"reset_noise_scale": -1.0}, "reset_noise_scale"),
        ({"width": 0}, "width"),
        ({"weights": (1.0, -1.0, 1.0)}, "non-negative"),
    ],
)
def test_bad_arguments_are_one_line_errors(kwargs, message):
    with pytest.raises(ValueError, match=message) as exc:
        PlanarWalkerEnv(**kwargs)
    assert "\n" not in str(exc.value)
