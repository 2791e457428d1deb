"""What a Gymnasium user runs: vector envs (sync, async, autoreset), standard wrappers, seeding."""

from __future__ import annotations

import gymnasium as gym
import numpy as np
import pytest
from gymnasium import wrappers

from ioc_bench import Demonstration

ENV_ID = "envs:IOCBench/PlanarWalker-v2"


@pytest.mark.parametrize("mode", ["sync", "async"])
def test_make_vec_steps_and_reports_gait_info(mode):
    vec = gym.make_vec(ENV_ID, num_envs=2, vectorization_mode=mode)
    obs, info = vec.reset(seed=[0, 1])
    assert obs.shape == (2, 17)
    assert not np.array_equal(obs[0], obs[1])  # different seeds, different starts
    assert set(info["stance_leg"]) <= {"a", "b"}
    obs, reward, terminated, truncated, info = vec.step(np.zeros((2, 4), dtype=np.float32))
    assert not terminated.any() and not truncated.any()
    assert reward.shape == (2,) and np.all(np.isfinite(reward))
    assert list(info["heel_strikes"]) == [0, 0]
    vec.close()


def test_autoreset_keeps_starting_from_the_demonstration(nominal_demo: Demonstration):
    """Vector autoreset passes no options: the ``demonstration`` argument still applies."""
    # A hip height range the demonstration starts outside of ends every episode at once.
    vec = gym.make_vec(
        ENV_ID, num_envs=2, vectorization_mode="sync", demonstration=nominal_demo, healthy_z_range=(1.5, 2.0)
    )
    first, _ = vec.reset(seed=0)
    _, _, terminated, _, _ = vec.step(np.zeros((2, 4), dtype=np.float32))
    assert terminated.all()
    again, _, _, _, info = vec.step(np.zeros((2, 4), dtype=np.float32))  # the autoreset step
    assert np.array_equal(again, first)
    assert list(info["heel_strikes"]) == [0, 0]
    vec.close()


def test_standard_wrappers_run():
    env = gym.make(ENV_ID)
    env = wrappers.RecordEpisodeStatistics(env)
    env = wrappers.NormalizeObservation(env)
    env = wrappers.NormalizeReward(env)
    env = wrappers.RescaleAction(env, -0.5, 0.5)
    env = wrappers.ClipAction(env)  # unbounded actions outside, clipped to the rescaled box
    env = wrappers.FrameStackObservation(env, 3)
    obs, _ = env.reset(seed=0)
    assert obs.shape == (3, 17)
    episodes = 0
    for _ in range(400):
        obs, reward, terminated, truncated, info = env.step(env.action_space.sample())
        assert np.all(np.isfinite(obs)) and np.isfinite(reward)
        if terminated or truncated:
            assert "episode" in info
            episodes += 1
            env.reset()
    assert episodes >= 1  # random torques make it fall
    env.close()


def test_seeding_makes_episodes_reproducible():
    def rollout(seed: int) -> np.ndarray:
        env = gym.make(ENV_ID)
        env.action_space.seed(seed)
        obs, _ = env.reset(seed=seed)
        out = [obs]
        for _ in range(30):
            out.append(env.step(env.action_space.sample())[0])
        env.close()
        return np.array(out)

    assert np.array_equal(rollout(3), rollout(3))
    assert not np.array_equal(rollout(3), rollout(4))


@pytest.mark.parametrize("old", ["v0", "v1"])
def test_old_versions_point_to_the_new_one(old):
    import envs  # noqa: F401  (registers the id)

    with pytest.raises(gym.error.DeprecatedEnv, match="v2"):
        gym.make(f"IOCBench/PlanarWalker-{old}")


def test_async_vector_env_tracks_a_demonstration(nominal_demo: Demonstration):
    """The demonstration argument and the policy cross process boundaries (pickled)."""
    import envs

    policy = envs.TrackingPolicy(nominal_demo)
    vec = gym.make_vec(ENV_ID, num_envs=2, vectorization_mode="async", demonstration=nominal_demo)
    obs, info = vec.reset(seed=0)
    for _ in range(int(1.5 * nominal_demo.trajectory.duration / 0.01)):
        obs, _, terminated, _, info = vec.step(policy(obs, info))
        assert not terminated.any()
    assert list(info["heel_strikes"]) == [1, 1] and list(info["stance_leg"]) == ["b", "b"]
    vec.close()
