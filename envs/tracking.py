"""A demonstration as a policy: feed-forward torques plus PD tracking, indexed by the step's phase.

A demonstration is one step at Hermite-Simpson knots with torques named by role (stance,
swing); the environment steps at its own ``dt`` and names torques by physical leg. The
:class:`TrackingPolicy` bridges the two for ``env.step``:

- **Phase, not clock.** The reference time is the one at which the demonstration's hip
  was as far ahead of its stance foot as the observed hip is now (that distance grows
  steadily through every demonstrated step). The walker's forward rotation about its
  foot is unactuated, and a clock-indexed reference lets it drift into another gait
  (measured on the replay: steps 60 % longer after five steps). Reference joint rates are
  scaled by the actual over the reference phase rate.
- **Feed-forward plus PD.** The demonstration's torques at that time (quadratic per
  interval, as Hermite-Simpson assumes) plus joint-space PD on the four actuated joints.
- **Legs by role.** ``info["stance_leg"]`` (reported by the environment, which detects
  heel strikes) says which physical leg plays the stance role; the torques are mapped to
  the motors accordingly, so they swap at every heel strike.
- **The step ends where the demonstration's ends.** Once the hip is further ahead of the
  stance foot than at the demonstration's last knot, the demonstrated step is over and the
  next one (the same step with the legs' roles swapped: the demonstration is one period
  of a periodic gait) has begun, whether or not the environment has seen the swing foot
  land yet: the policy then tracks the next step, phased by the hip's distance ahead of
  the swing foot. The benchmark's optimal steps put the swing foot down with zero velocity
  and no impact, tangentially to the ground; a tracking error of 1e-4 leaves it hovering
  that high at the step's end, and holding the last knot's reference until it touched
  made the steps 8 % longer than the demonstration's and the walk drift into another
  gait (docs/notes/2026-11-25-grazing-swing-feet.md).

The policy keeps no state between calls: everything comes from the observation and
``info``, so one policy serves every environment of a vector environment.
"""

from __future__ import annotations

import os
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

from envs.coordinates import actuated_dofs, check_stance, motor_controls, other_leg
from envs.observation import ObservedState, split_observation
from envs.reference import DemoReference, hip_over_foot
from ioc_bench.demo import Demonstration


@dataclass(frozen=True)
class PDGains:
    """Joint-space PD gains, the same for the four actuated joints.

    The defaults were picked on nominal-weight steps at speed 0.27 (1 and 15 starts, and
    the +10 % leg-mass walker) from kp in {2, 3, 4} and kd in {0.1, 0.15, 0.2} with
    control at every physics step: every pair walked 10 steps with a feedback share of
    9-16 %. Through the environment (control every ``dt`` = 0.01) they still walk; the
    shares are in docs/notes/2026-11-25-grazing-swing-feet.md.

    Attributes:
        kp: stiffness (torque per rad, units m g L).
        kd: damping (torque per rad per time unit).
    """

    kp: float = 3.0
    kd: float = 0.15

    def __post_init__(self) -> None:
        for name in ("kp", "kd"):
            value = getattr(self, name)
            if not (np.isfinite(value) and value >= 0):
                raise ValueError(f"PD gain {name} must be a finite number >= 0, got {value}")


@dataclass(frozen=True, eq=False)
class TrackingCommand:
    """One decision of the policy, joint quantities in ``ACTUATORS`` (role) order.

    Attributes:
        stance_leg: the physical leg tracked in the stance role (the environment's stance
            leg, or the other once the hip has passed the end of the demonstrated step).
        phase: the reference time matching the observed hip-over-foot distance.
        rate: the observed over the reference phase rate.
        joints: (4,) observed actuated joint angles (rad).
        joints_ref: (4,) their reference at ``phase``.
        tau_ff: (4,) the demonstration's torques at ``phase``.
        tau_fb: (4,) the PD torques.
        action: (4,) the motor torques to send (``MOTORS`` order, clipped to the bound).
    """

    stance_leg: str
    phase: float
    rate: float
    joints: np.ndarray
    joints_ref: np.ndarray
    tau_ff: np.ndarray
    tau_fb: np.ndarray
    action: np.ndarray


class TrackingPolicy:
    """Track a demonstration through ``env.step``: ``action = policy(observation, info)``.

    Works on one environment (``observation`` of shape (17,) or (18,), ``info`` a dict)
    and on a vector environment (``observation`` of shape (n, 17) or (n, 18), ``info``
    the vector info whose ``stance_leg`` is an array of n leg names). The environment
    must start from the demonstration (``demonstration=`` argument or reset option).

    Args:
        demonstration: a ``Demonstration`` or the path of one.
        gains: PD gains (default :class:`PDGains`).

    Raises:
        ValueError: if the demonstration's hip does not move steadily forward over its
            stance foot (its phase would not identify a time).
    """

    def __init__(self, demonstration: Demonstration | str | os.PathLike, gains: PDGains | None = None):
        if not isinstance(demonstration, Demonstration):
            demonstration = Demonstration.load(demonstration)
        self.demonstration = demonstration
        self.gains = gains or PDGains()
        self.reference = DemoReference.of(demonstration)
        self._path_t, self._path_x, self._path_xd = self.reference.phase_path()
        self._max_torque = float(demonstration.params.max_torque)

    def __call__(self, observation: np.ndarray, info: Mapping[str, Any]) -> np.ndarray:
        """Motor torques, float32: (4,) for one observation, (n, 4) for a batch."""
        obs = np.asarray(observation)
        if obs.ndim == 1:
            return self.command(obs, info).action.astype(np.float32)
        legs = np.asarray(_stance_legs(info)).reshape(-1)
        if obs.ndim != 2 or legs.shape[0] != obs.shape[0]:
            raise ValueError(f"expected n observations and n stance legs, got shapes {obs.shape} and {legs.shape}")
        rows = [self.command(o, {"stance_leg": str(leg)}).action for o, leg in zip(obs, legs)]
        return np.array(rows, dtype=np.float32)

    def command(self, observation: np.ndarray, info: Mapping[str, Any]) -> TrackingCommand:
        """The full decision for one observation, with its parts (for checks and plots).

        ``stance_leg`` of the result is the leg tracked in the stance role: the
        environment's, or the other one once the hip has passed the demonstrated step's end.
        """
        state = split_observation(observation)
        stance = self.tracked_stance(state, check_stance(str(_stance_legs(info))))
        t, rate = self.phase(state, stance)
        dofs = actuated_dofs(stance)
        q = np.array([state.qpos_at(i) for i in dofs])
        qd = state.qvel[dofs]
        q_ref, qd_ref = self.reference.joints(t)
        fb = self.gains.kp * (q_ref - q) + self.gains.kd * (rate * qd_ref - qd)
        ff = self.reference.torque(t)
        action = np.clip(motor_controls(ff + fb, stance), -self._max_torque, self._max_torque)
        return TrackingCommand(stance, t, rate, q, q_ref, ff, fb, action)

    def tracked_stance(self, state: ObservedState, stance: str) -> str:
        """The leg to track in the stance role, given the environment's stance leg.

        The demonstrated step ends where the hip is as far ahead of the stance foot as at
        its last knot; past that, the next step, with the roles swapped, is tracked even
        if the environment has not seen the swing foot land yet (it hovers).
        """
        if self._hip_over_foot(state, stance)[0] > self._path_x[-1]:
            return other_leg(stance)
        return stance

    def phase(self, state: ObservedState, stance: str) -> tuple[float, float]:
        """Reference time matching the hip's distance ahead of the stance foot, and the phase rate."""
        x, _ = self._hip_over_foot(state, stance)
        t = float(np.interp(x, self._path_x, self._path_t))
        return t, float(state.qvel[0]) / float(np.interp(t, self._path_t, self._path_xd))

    def _hip_over_foot(self, state: ObservedState, stance: str) -> tuple[float, float]:
        """The hip's forward position and velocity relative to leg ``stance``'s foot."""
        link = self.reference.linkage
        theta, omega = np.zeros(len(link.segments)), np.zeros(len(link.segments))
        torso = link.index("torso")
        theta[torso], omega[torso] = state.qpos_at(2), state.qvel[2]
        hip_dofs, knee_dofs = actuated_dofs(stance)[:2], actuated_dofs(stance)[2:]
        for leg_role, hip, knee in zip(("stance", "swing"), hip_dofs, knee_dofs):
            thigh, shank = link.index(f"thigh_{leg_role}"), link.index(f"shank_{leg_role}")
            theta[thigh], omega[thigh] = theta[torso] + state.qpos_at(hip), omega[torso] + state.qvel[hip]
            theta[shank], omega[shank] = theta[thigh] + state.qpos_at(knee), omega[thigh] + state.qvel[knee]
        return hip_over_foot(link, theta, omega)


def _stance_legs(info: Mapping[str, Any]) -> Any:
    try:
        return info["stance_leg"]
    except (KeyError, TypeError):
        raise ValueError(
            "info has no 'stance_leg': pass the info of IOCBench/PlanarWalker-v2's reset or step"
        ) from None


__all__ = ["PDGains", "TrackingCommand", "TrackingPolicy"]
