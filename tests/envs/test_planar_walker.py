"""The Gymnasium environment: API conformance, reward bookkeeping, resets, rendering."""

from __future__ import annotations

import os
import pickle
import subprocess
import sys
import warnings
from dataclasses import replace

import gymnasium as gym
import numpy as np
import pytest
from gymnasium.utils.env_checker import check_env

from envs.planar_walker import REWARD_TERMS, PlanarWalkerEnv
from ioc_bench import Demonstration, WalkerParams
from ioc_bench.features import COST_FEATURES
from ioc_bench.weights import parse_weights

ENV_ID = "envs:IOCBench/PlanarWalker-v2"


#: The passive checker's only complaints: unbounded observations, deliberate (Walker2d-v5 gets the same two).
UNBOUNDED_WARNINGS = {"observation space minimum value is -infinity", "observation space maximum value is infinity"}


@pytest.mark.parametrize("render_mode", [None, "rgb_array"])
def test_check_env_passes_with_only_the_unbounded_space_warnings(render_mode):
    """Also covers the default renderer: MuJoCo's if OpenGL works here, else the stick figure."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        env = gym.make(ENV_ID, render_mode=render_mode)
        check_env(env.unwrapped)
        env.close()
    messages = [str(w.message) for w in caught]
    assert len(messages) == 2
    assert all(any(known in m for known in UNBOUNDED_WARNINGS) for m in messages), messages


def test_reward_is_the_sum_of_its_terms(rng):
    env = PlanarWalkerEnv(weights=(1.0, 2.0, 3.0))
    env.reset(seed=0)
    w = parse_weights((1.0, 2.0, 3.0))
    for i in range(20):
        action = rng.uniform(-0.05, 0.05, size=4).astype(np.float32)
        _, reward, terminated, truncated, info = env.step(action)
        assert reward == sum(info[k] for k in REWARD_TERMS)  # exactly
        assert isinstance(reward, float) and isinstance(terminated, bool) and truncated is False
        assert info["reward_forward"] == pytest.approx(info["x_velocity"])
        for weight, name in zip(w, COST_FEATURES):
            assert info[f"reward_{name}"] == pytest.approx(-weight * info[f"phi_{name}"])
        tau = action.astype(float)
        g = 9.81  # the paper's units: N m and s for a 1 m, 1 kg walker, so tau^2 dt scales by g^1.5
        assert info["phi_hip"] == pytest.approx(g**1.5 * (tau[0] ** 2 + tau[1] ** 2) * env.dt)
        assert info["phi_knee"] == pytest.approx(g**1.5 * (tau[2] ** 2 + tau[3] ** 2) * env.dt)
        if i == 0:
            assert info["phi_dtau"] == 0.0  # no torque before the first step


def test_cost_features_accumulate_like_the_optimizers(nominal_demo: Demonstration):
    """Per-step increments of a torque sequence, summed and divided by the duration in seconds,
    equal ioc-bench's features (effort per unit time)."""
    from ioc_bench.features import evaluate

    tr = nominal_demo.trajectory
    env = PlanarWalkerEnv(frame_skip=1)
    env.reset(seed=0)
    sums = dict.fromkeys(COST_FEATURES, 0.0)
    dt = env.dt
    for tau in tr.tau:
        info = env.step(tau.astype(np.float32))[4]
        for name in COST_FEATURES:
            sums[name] += info[f"phi_{name}"]
    # The same torques on knots spaced like the env's steps.
    expected = evaluate(replace(tr, dt=dt), nominal_demo.params, COST_FEATURES)
    seconds = (tr.n_knots - 1) * dt / np.sqrt(9.81)
    for name in COST_FEATURES:
        assert sums[name] / seconds == pytest.approx(expected[name], rel=1e-5)


def test_reset_from_a_demonstration_is_its_initial_state(nominal_demo: Demonstration, tmp_path):
    from envs.reference import DemoReference

    env = PlanarWalkerEnv(exclude_current_positions_from_observation=False)
    obs, info = env.reset(seed=3, options={"demonstration": nominal_demo})
    ref = DemoReference.of(nominal_demo)
    assert obs == pytest.approx(np.concatenate([ref.qpos[0], ref.qvel[0], np.zeros(4)]), abs=1e-12)
    assert info["x_position"] == pytest.approx(ref.qpos[0, 0])
    assert info["stance_leg"] == "a" and info["heel_strikes"] == 0
    path = nominal_demo.save(tmp_path / "demo.npz")
    obs2, _ = env.reset(options={"demonstration": str(path)})
    assert obs2 == pytest.approx(obs)


def test_reset_rejects_unknown_options_and_foreign_geometry(nominal_demo: Demonstration):
    env = PlanarWalkerEnv()
    with pytest.raises(ValueError, match="unknown reset option"):
        env.reset(options={"demo": nominal_demo})
    other = PlanarWalkerEnv(params=WalkerParams(friction=0.8))
    other.reset(options={"demonstration": nominal_demo})  # friction differs, geometry does not
    longer = replace(WalkerParams(), thigh=replace(WalkerParams().thigh, length=0.5))
    with pytest.raises(ValueError, match="segment lengths"):
        PlanarWalkerEnv(params=longer).reset(options={"demonstration": nominal_demo})


def test_default_start_is_seeded_and_on_the_ground():
    env = PlanarWalkerEnv()
    a, _ = env.reset(seed=7)
    b, _ = env.reset(seed=7)
    c, _ = env.reset(seed=8)
    assert np.array_equal(a, b) and not np.array_equal(a, c)
    feet = [env.data.site(f"foot_{leg}").xpos[2] for leg in "ab"]
    assert min(feet) == pytest.approx(0.0, abs=1e-12)
    assert env.data.qpos[[4, 6]].min() >= 0.0  # knees inside their range


def test_falls_terminate_the_episode():
    env = gym.make(ENV_ID)
    env.reset(seed=0)
    for _ in range(1000):
        _, _, terminated, truncated, _ = env.step(np.zeros(4, dtype=np.float32))
        if terminated or truncated:
            break
    assert terminated, "a walker without torques should fall"
    assert env.unwrapped.data.qpos[1] < 0.6 or abs(env.unwrapped.data.qpos[2]) > 1.0


def test_model_variant_is_an_argument():
    heavy = WalkerParams().with_leg_mass_scale(1.1)
    env = gym.make(ENV_ID, params=heavy)
    assert env.unwrapped.model.body("shank_a").mass[0] == pytest.approx(heavy.shank.mass)
    assert env.action_space.high == pytest.approx(np.full(4, heavy.max_torque))


def test_pickles_with_its_arguments():
    env = PlanarWalkerEnv(weights="penalize-hip", frame_skip=10)
    clone = pickle.loads(pickle.dumps(env))
    assert clone.frame_skip == 10 and clone.dt == pytest.approx(env.dt)
    assert clone.weights == pytest.approx(env.weights)


def test_stick_rendering_is_headless_and_follows_the_walker(nominal_demo: Demonstration):
    env = PlanarWalkerEnv(render_mode="rgb_array", renderer="stick", width=160, height=120)
    env.reset(options={"demonstration": nominal_demo})
    first = env.render()
    assert first.shape == (120, 160, 3) and first.dtype == np.uint8
    assert first.std() > 0
    for _ in range(10):
        env.step(np.zeros(4, dtype=np.float32))
    assert not np.array_equal(env.render(), first)
    assert env.renderer_in_use == "stick"
    env.close()
    env.close()  # closing twice is allowed
    assert PlanarWalkerEnv().render() is None


def test_bad_arguments_are_rejected():
    with pytest.raises(ValueError, match="render_mode"):
        PlanarWalkerEnv(render_mode="human")
    with pytest.raises(ValueError, match="renderer"):
        PlanarWalkerEnv(renderer="vulkan")
    with pytest.raises(ValueError, match="weight"):
        PlanarWalkerEnv(weights="heavy")


def test_mujoco_rendering_with_egl():
    """MuJoCo's own renderer, where an EGL driver exists (skipped on pip-only machines)."""
    code = (
        "import gymnasium as gym, numpy as np\n"
        "env = gym.make('envs:IOCBench/PlanarWalker-v2', render_mode='rgb_array', renderer='mujoco', "
        "width=64, height=48)\n"
        "env.reset(seed=0)\n"
        "img = env.render()\n"
        "assert img.shape == (48, 64, 3) and img.std() > 0\n"
        "print(type(env.unwrapped._drawer).__name__, env.unwrapped.renderer_in_use)\n"
    )
    out = subprocess.run(
        [sys.executable, "-c", code], env={**os.environ, "MUJOCO_GL": "egl"}, capture_output=True, text=True
    )
    if out.returncode != 0:
        pytest.skip(f"no EGL rendering here: {out.stderr.strip().splitlines()[-1:]}")
    assert out.stdout.strip() == "Renderer mujoco"
