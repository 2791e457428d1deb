"""Gymnasium environments and MuJoCo replay checks for the ioc-bench walker.

Importing this package registers ``IOCBench/PlanarWalker-v0`` by string entry point, so
MuJoCo is imported only when the environment is made::

    import gymnasium as gym

    env = gym.make("envs:IOCBench/PlanarWalker-v0")  # imports ``envs``, then makes the env
    # or: import envs; gym.register_envs(envs); env = gym.make("IOCBench/PlanarWalker-v0")

Gymnasium 1.x has no plugin entry-point group, hence the ``module:id`` form above.
"""

from __future__ import annotations

import gymnasium

#: The environment id; bump ``vN`` whenever dynamics, observations or reward change.
PLANAR_WALKER_ID = "IOCBench/PlanarWalker-v0"

if PLANAR_WALKER_ID not in gymnasium.registry:
    gymnasium.register(
        id=PLANAR_WALKER_ID,
        entry_point="envs.planar_walker:PlanarWalkerEnv",
        max_episode_steps=1000,
    )

__all__ = ["PLANAR_WALKER_ID"]
