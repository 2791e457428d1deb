"""Gymnasium environment, demonstration-tracking policy and MuJoCo replay checks for the ioc-bench walker.

Importing this package registers ``IOCBench/PlanarWalker-v2`` by string entry point, so
MuJoCo is imported only when the environment is made::

    import gymnasium as gym

    env = gym.make("envs:IOCBench/PlanarWalker-v2")  # imports ``envs``, then makes the env
    # or: import envs; gym.register_envs(envs); env = gym.make("IOCBench/PlanarWalker-v2")

Gymnasium 1.x has no plugin entry-point group, hence the ``module:id`` form above.

A demonstration becomes a policy with :class:`envs.TrackingPolicy`::

    policy = envs.TrackingPolicy(demo)
    obs, info = env.reset(options={"demonstration": demo})
    obs, reward, terminated, truncated, info = env.step(policy(obs, info))

Modules: ``planar_walker`` (the environment), ``observation`` (its layout), ``state``
(``get_state`` snapshots), ``heel_strikes`` (stance leg and heel strikes), ``tracking``
(the policy), ``reference`` (a demonstration as a reference), ``checks`` (the replay
checks: inverse dynamics, open loop, closed loop), ``plots`` (their figure and GIF).
"""

from __future__ import annotations

from typing import Any

import gymnasium

#: The environment id; bump ``vN`` whenever dynamics, observations or reward change.
PLANAR_WALKER_ID = "IOCBench/PlanarWalker-v2"

if PLANAR_WALKER_ID not in gymnasium.registry:
    gymnasium.register(
        id=PLANAR_WALKER_ID,
        entry_point="envs.planar_walker:PlanarWalkerEnv",
        max_episode_steps=1000,
    )

#: Public names imported on first use (they import MuJoCo or the optimizer's modules).
_LAZY = {
    "PlanarWalkerEnv": "envs.planar_walker",
    "WalkerState": "envs.state",
    "TrackingPolicy": "envs.tracking",
    "PDGains": "envs.tracking",
}


def __getattr__(name: str) -> Any:
    if name in _LAZY:
        import importlib

        return getattr(importlib.import_module(_LAZY[name]), name)
    raise AttributeError(f"module 'envs' has no attribute {name!r}")


__all__ = ["PLANAR_WALKER_ID", "PDGains", "PlanarWalkerEnv", "TrackingPolicy", "WalkerState"]
