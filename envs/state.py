"""The full state of a ``PlanarWalkerEnv``: everything the next ``step`` depends on.

MuJoCo's ``qpos`` and ``qvel`` are not all of it: the next step also reads the time, the
constraint solver's warm start and the applied forces (MuJoCo's ``mjSTATE_INTEGRATION``
bundle), and the environment's own bookkeeping: the previous torque (the ``dtau`` reward
term), the stance leg (which also decides which foot has friction) and heel-strike count
(``info``), the episode's landing distance (``envs.heel_strikes``) and its reward weights.
:meth:`PlanarWalkerEnv.set_state` of a :meth:`PlanarWalkerEnv.get_state` restores all of it,
so the next step is bit-for-bit the one the original would have taken.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from envs.coordinates import check_stance
from ioc_bench.model.mjcf import JOINTS, MOTORS

_NQ = _NV = len(JOINTS)


def _frozen(values: np.ndarray) -> np.ndarray:
    arr = np.array(values, dtype=float)
    arr.flags.writeable = False
    return arr


@dataclass(frozen=True, eq=False)
class WalkerState:
    """A snapshot of the environment (read-only arrays).

    Attributes:
        physics: MuJoCo's ``mjSTATE_INTEGRATION`` vector (``mj_getState``): time, qpos,
            qvel, warm start, controls, applied forces, in MuJoCo's order.
        previous_torque: (4,) the last applied torque, ``MOTORS`` order; None right after
            a reset (the first step's ``dtau`` term is then 0).
        stance_leg: the physical leg in the stance role ("a" or "b"); its foot has
            friction, the other's not.
        swing_lifted: whether the swing foot has been off the floor since the last heel strike.
        heel_strikes: heel strikes since the reset.
        weights: (3,) unit-norm reward weights of the episode over (hip, knee, dtau).
        landing_distance: how far ahead of the stance foot a touchdown counts as the
            landing (from the episode's demonstration; 0 for a standing start).
    """

    physics: np.ndarray
    previous_torque: np.ndarray | None
    stance_leg: str
    swing_lifted: bool
    heel_strikes: int
    weights: np.ndarray
    landing_distance: float = 0.0

    def __post_init__(self) -> None:
        object.__setattr__(self, "physics", _frozen(self.physics))
        if self.physics.ndim != 1 or self.physics.shape[0] < 1 + _NQ + _NV:
            raise ValueError(f"physics must be MuJoCo's integration state vector, got shape {self.physics.shape}")
        if self.previous_torque is not None:
            object.__setattr__(self, "previous_torque", _frozen(self.previous_torque))
            if self.previous_torque.shape != (len(MOTORS),):
                raise ValueError(f"previous_torque must have shape ({len(MOTORS)},), got {self.previous_torque.shape}")
        check_stance(self.stance_leg)
        object.__setattr__(self, "weights", _frozen(self.weights))

    @property
    def time(self) -> float:
        """Simulation time (MuJoCo's ``data.time``)."""
        return float(self.physics[0])

    @property
    def qpos(self) -> np.ndarray:
        """(7,) generalized positions, ``JOINTS`` order."""
        return self.physics[1 : 1 + _NQ]

    @property
    def qvel(self) -> np.ndarray:
        """(7,) generalized velocities, ``JOINTS`` order."""
        return self.physics[1 + _NQ : 1 + _NQ + _NV]
