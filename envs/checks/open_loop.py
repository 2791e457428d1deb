"""Check 2, open loop: the step simulated in the environment with the demonstration's torques alone.

From the demonstration's initial state, ``env.step`` applies the demonstration's torques,
quadratic in each interval as Hermite-Simpson assumes, on soft ground with the knee limit
acting as the knee-lock. For this the environment is made with one physics step per
action (``frame_skip=1``) and a physics timestep dividing the knot spacing, so the
torques change at physics resolution and the state is sampled exactly at every knot.
The timestep is the generated model's fine 0.0005 (shrunk to divide the knot spacing),
not the environment's 0.002: walking is unstable, so integration error grows with the
drift (measured over eight demonstrations against a 16x finer step: median 1.4e-3 at
0.0005, 4.6e-3 at 0.002, for a drift from the demonstration of 7.8e-2).
Walking is unstable, so the simulation drifts; the final-state error is reported, not
judged. The landing reported is the environment's heel strike (a touchdown in the landing
zone, not a mid-swing graze: see ``envs.heel_strikes``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import Any

import numpy as np

from envs.coordinates import motor_controls
from envs.physics import MujocoParams
from envs.reference import DemoReference
from ioc_bench.demo import Demonstration
from ioc_bench.model.mjcf import JOINTS, ContactSettings


@dataclass(frozen=True, eq=False)
class OpenLoopResult:
    """The step simulated with the demonstration's torques alone.

    Attributes:
        times: (T,) knot times.
        qpos, qvel: (T, 7) simulated state at each knot time.
        qpos_ref, qvel_ref: (T, 7) the demonstration's state at the knots.
        final_position_error: max |qpos - qpos_ref| at the last knot (leg lengths or rad).
        final_velocity_error: max |qvel - qvel_ref| at the last knot.
        touchdown_time: time of the environment's first heel strike, the swing foot landing
            (None if not before the end).
        timestep: the physics timestep used (divides the knot spacing).
    """

    times: np.ndarray
    qpos: np.ndarray
    qvel: np.ndarray
    qpos_ref: np.ndarray
    qvel_ref: np.ndarray
    final_position_error: float
    final_velocity_error: float
    touchdown_time: float | None
    timestep: float

    @property
    def position_error(self) -> np.ndarray:
        """(T,) max |qpos - qpos_ref| at each knot."""
        return np.abs(self.qpos - self.qpos_ref).max(axis=1)

    def to_dict(self) -> dict[str, Any]:
        return {
            "final_position_error": self.final_position_error,
            "final_velocity_error": self.final_velocity_error,
            "final_position_error_by_dof": dict(zip(JOINTS, np.abs(self.qpos - self.qpos_ref)[-1].tolist())),
            "touchdown_time": self.touchdown_time,
            "duration": float(self.times[-1]),
            "timestep": self.timestep,
        }


def knot_aligned(contact: ContactSettings | None, knot_spacing: float) -> ContactSettings:
    """``contact`` (default: the generated model's) with its timestep shrunk to divide ``knot_spacing``."""
    contact = contact or ContactSettings()
    n = max(1, math.ceil(knot_spacing / contact.timestep - 1e-9))
    return replace(contact, timestep=knot_spacing / n)


def open_loop_replay(
    demo: Demonstration,
    params: MujocoParams | None = None,
    contact: ContactSettings | None = None,
) -> OpenLoopResult:
    """Simulate one step from the demonstration's initial state with its torques alone.

    Args:
        demo: the demonstration.
        params: the MuJoCo model (default: the demonstration's own).
        contact: contact settings; the timestep is shrunk to divide the knot spacing.
    """
    from envs.planar_walker import PlanarWalkerEnv

    ref = DemoReference.of(demo)
    settings = knot_aligned(contact, ref.dt)
    per_knot = round(ref.dt / settings.timestep)
    env = PlanarWalkerEnv(
        params=params or demo.params,
        demonstration=demo,
        frame_skip=1,
        terminate_when_unhealthy=False,
        contact=settings,
    )
    env.reset()
    states = [env.state_vector()]
    touchdown = None
    for k in range(1, len(ref.times)):
        for i in range(per_knot):
            t = ref.times[k - 1] + i * settings.timestep
            info = env.step(motor_controls(ref.torque(t), "a"))[4]
            if touchdown is None and info["heel_strikes"] > 0:
                touchdown = float(t + settings.timestep)
        states.append(env.state_vector())
    env.close()
    sim = np.array(states)
    qpos, qvel = sim[:, : len(JOINTS)], sim[:, len(JOINTS) :]
    return OpenLoopResult(
        times=ref.times,
        qpos=qpos,
        qvel=qvel,
        qpos_ref=ref.qpos,
        qvel_ref=ref.qvel,
        final_position_error=float(np.abs(qpos[-1] - ref.qpos[-1]).max()),
        final_velocity_error=float(np.abs(qvel[-1] - ref.qvel[-1]).max()),
        touchdown_time=touchdown,
        timestep=settings.timestep,
    )
