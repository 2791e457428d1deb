"""The layout of ``IOCBench/PlanarWalker-v2``'s observation, for the env and for policies.

An observation is ``[qpos[1:], qvel, previous torque]`` (17 numbers), or with the hip's
forward position kept (``exclude_current_positions_from_observation=False``)
``[qpos, qvel, previous torque]`` (18). Nothing is clipped or wrapped: the entries are
MuJoCo's ``qpos`` and ``qvel`` as they are (angles in rad, unbounded, so a hip that turned
a full circle is told apart), and the previous torque is the last action as applied
(clipped to the torque bound, motor order), zero after a reset. The previous torque is
there because the ``dtau`` reward term depends on it.

This module does not import MuJoCo.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ioc_bench.model.mjcf import JOINTS, MOTORS

#: Names of the observation's entries with the hip's x excluded (the default), in order.
OBSERVATION_NAMES: tuple[str, ...] = (
    *(f"qpos_{j}" for j in JOINTS[1:]),
    *(f"qvel_{j}" for j in JOINTS),
    *(f"previous_torque_{m}" for m in MOTORS),
)
#: Names with the hip's x kept (``exclude_current_positions_from_observation=False``).
OBSERVATION_NAMES_WITH_X: tuple[str, ...] = (f"qpos_{JOINTS[0]}", *OBSERVATION_NAMES)


def observation_names(exclude_x: bool = True) -> tuple[str, ...]:
    """Names of the observation's entries, in order."""
    return OBSERVATION_NAMES if exclude_x else OBSERVATION_NAMES_WITH_X


@dataclass(frozen=True, eq=False)
class ObservedState:
    """One observation taken apart.

    Attributes:
        x: the hip's forward position (None when the observation excludes it).
        positions: (6,) ``qpos[1:]``: hip height, torso angle, hip_a, knee_a, hip_b, knee_b.
        qvel: (7,) generalized velocities, ``JOINTS`` order.
        previous_torque: (4,) the previous action as applied, ``MOTORS`` order.
    """

    x: float | None
    positions: np.ndarray
    qvel: np.ndarray
    previous_torque: np.ndarray

    def qpos_at(self, index: int) -> float:
        """``qpos[index]`` for ``index >= 1`` (the hip's x may be absent)."""
        if index < 1:
            raise ValueError("qpos[0] (the hip's x) is not in every observation; read ObservedState.x")
        return float(self.positions[index - 1])


def split_observation(observation: np.ndarray) -> ObservedState:
    """Take one observation apart (its length tells whether the hip's x is included).

    Raises:
        ValueError: if ``observation`` is not a 1-D vector of 17 or 18 numbers.
    """
    obs = np.asarray(observation, dtype=float)
    sizes = (len(OBSERVATION_NAMES), len(OBSERVATION_NAMES_WITH_X))
    if obs.ndim != 1 or obs.shape[0] not in sizes:
        raise ValueError(f"expected one observation of {sizes[0]} or {sizes[1]} numbers, got shape {obs.shape}")
    x = None
    if obs.shape[0] == sizes[1]:
        x, obs = float(obs[0]), obs[1:]
    nq = len(JOINTS) - 1
    nv = len(JOINTS)
    return ObservedState(x, obs[:nq], obs[nq : nq + nv], obs[nq + nv :])
