"""Check 3, closed loop: the demonstration walked for several steps by :class:`TrackingPolicy` through ``env.step``.

The environment starts from the demonstration's initial state and detects heel strikes
(the policy then swaps the legs' roles); the policy adds PD tracking to the
demonstration's torques, indexed by phase. This is the loop a Gymnasium user runs; only
the control period differs: the check decides every :data:`CHECK_CONTROL_DT` (the
environment's ``frame_skip`` set to match), not every 0.01. At 0.01 the sampled PD rings
after each heel strike and the feedback share measures that ringing more than the
demonstration (nominal step: 48 % at 0.01 and 14 % at every 0.002 physics step; with
v0's 0.0005 physics 37 % and 13 %; docs/notes/2026-11-25-env-physics-step-and-rates.md).
Reported: steps walked, tracking error (RMS and max over environment steps and the four
actuated joints, rad), and the feedback share
``sum |tau_fb| / (sum |tau_ff| + sum |tau_fb|)`` over every environment step and joint,
the share of steps ending with the stance foot on the floor, and the swing foot's
grazes (touchdowns short of the landing zone, which the environment does not count as
heel strikes). The walk stops early on a fall (the environment's termination) or when a step lasts
over :data:`MAX_STEP_FRACTION` times the demonstration's.
"""

from __future__ import annotations

import math
import os
from collections.abc import Iterable
from dataclasses import dataclass
from typing import Any

import numpy as np

from envs.coordinates import other_leg
from envs.physics import DEFAULT_CONTACT, HealthyRange, MujocoParams
from envs.tracking import PDGains, TrackingPolicy
from ioc_bench.demo import Demonstration
from ioc_bench.model.mjcf import JOINTS, ContactSettings

#: Feedback share at or above which the closed loop is reported as not following the
#: demonstration (reported, not judged: the physical verdict is ``envs.checks.physics_checks``).
FEEDBACK_SHARE_LIMIT = 0.2
#: Steps the closed loop walks by default.
DEFAULT_STEPS = 10
#: A step that has not ended after this multiple of the reference duration counts as a fall.
MAX_STEP_FRACTION = 2.0
#: Longest time between the check's control decisions (sqrt(L/g)); every physics step if
#: that is longer (so every 0.002 with the environment's physics).
CHECK_CONTROL_DT = 0.0025


@dataclass(frozen=True, eq=False)
class ClosedLoopResult:
    """The gait repeated under feed-forward plus PD tracking.

    Attributes:
        steps_requested: steps the replay tried to walk.
        steps_walked: heel strikes reached before a fall (or the end).
        fall_reason: why the walk stopped early (None if it walked every step).
        tracking_rms: RMS joint-angle error over all environment steps and actuated joints (rad).
        tracking_max: max |joint-angle error| (rad).
        feedback_share: ``sum |tau_fb| / (sum |tau_ff| + sum |tau_fb|)``.
        gains: the PD gains used.
        control_dt: time between the policy's decisions (the environment's ``dt``).
        times: (N,) times of the recorded frames (one per environment step).
        qpos: (N, 7) recorded states.
        stance: (N,) the leg tracked in the stance role ("a" or "b") at each frame (the
            environment's, or the next step's once the hip has passed the step's end).
        phase: (N,) reference time (phase) at each frame.
        joints: (N, 4) actual actuated joint angles, ``ACTUATORS`` (role) order.
        joints_ref: (N, 4) their reference.
        tau_ff, tau_fb: (N, 4) feed-forward and feedback torques, ``ACTUATORS`` order
            (the last frame, after the walk, has no action: its torques are the policy's
            decision there, not applied).
        heel_strikes: times of the heel strikes.
        stance_contact: fraction of environment steps that ended with the stance foot on
            the floor (the optimizer's stance foot never leaves it).
        grazes: touchdowns of the swing foot (after it had lifted off) that the
            environment did not count as heel strikes (short of the landing zone).
        share_limit: feedback share at or above which the walk is reported as not following
            the demonstration (:attr:`passed`; the replay reports it, it does not judge by it).
    """

    steps_requested: int
    steps_walked: int
    fall_reason: str | None
    tracking_rms: float
    tracking_max: float
    feedback_share: float
    gains: PDGains
    control_dt: float
    times: np.ndarray
    qpos: np.ndarray
    stance: np.ndarray
    phase: np.ndarray
    joints: np.ndarray
    joints_ref: np.ndarray
    tau_ff: np.ndarray
    tau_fb: np.ndarray
    heel_strikes: tuple[float, ...]
    stance_contact: float
    grazes: int
    share_limit: float = FEEDBACK_SHARE_LIMIT

    @property
    def passed(self) -> bool:
        """Walked every step with a feedback share under :attr:`share_limit` ("followed" in
        :meth:`to_dict`). A stability figure, not the verdict: a valid gait may miss it (the
        verdict is the physical checks', :mod:`envs.checks.physics_checks`)."""
        return self.steps_walked >= self.steps_requested and self.feedback_share < self.share_limit

    def to_dict(self) -> dict[str, Any]:
        return {
            "steps_requested": self.steps_requested,
            "steps_walked": self.steps_walked,
            "fall_reason": self.fall_reason,
            "tracking_rms": self.tracking_rms,
            "tracking_max": self.tracking_max,
            "feedback_share": self.feedback_share,
            "share_limit": self.share_limit,
            "gains": {"kp": self.gains.kp, "kd": self.gains.kd},
            "control_dt": self.control_dt,
            "step_durations": np.diff((0.0, *self.heel_strikes)).tolist(),
            "stance_contact": self.stance_contact,
            "grazes": self.grazes,
            "distance": float(self.qpos[-1, 0] - self.qpos[0, 0]),
            "followed": self.passed,
        }


def closed_loop_replay(
    demo: Demonstration,
    steps: int = DEFAULT_STEPS,
    gains: PDGains | None = None,
    params: MujocoParams | None = None,
    healthy: HealthyRange | None = None,
    contact: ContactSettings | None = None,
    control_dt: float | None = CHECK_CONTROL_DT,
) -> ClosedLoopResult:
    """Walk ``steps`` steps with :class:`TrackingPolicy` in the environment.

    Args:
        demo: the demonstration; its initial state starts the walk with leg ``a`` in stance.
        steps: heel strikes to reach.
        gains: PD gains (default :class:`PDGains`).
        params: the MuJoCo model (default: the demonstration's own).
        healthy: fall criterion (default :class:`HealthyRange`).
        contact: contact settings and physics timestep of the MuJoCo model.
        control_dt: longest time between the policy's decisions: the most whole physics
            steps within it (at least one); None: the environment's default ``dt``.
    """
    from envs.planar_walker import PlanarWalkerEnv

    if steps < 1:
        raise ValueError(f"steps must be >= 1, got {steps}")
    policy = TrackingPolicy(demo, gains)
    healthy = healthy or HealthyRange()
    timestep = (contact or DEFAULT_CONTACT).timestep
    skip = {} if control_dt is None else {"frame_skip": max(1, math.floor(control_dt / timestep + 1e-9))}
    env = PlanarWalkerEnv(
        params=params or demo.params,
        demonstration=demo,
        healthy_z_range=healthy.hip_z,
        healthy_angle_range=healthy.torso_angle,
        contact=contact,
        **skip,
    )
    obs, info = env.reset()
    duration = policy.reference.duration
    frames, strikes, reason, step_start, touching = [], [], None, 0.0, []
    grazes, swing_lifted = 0, False
    while len(strikes) < steps and reason is None:
        cmd = policy.command(obs, info)
        frames.append((env.data.time, env.state_vector()[: len(JOINTS)], cmd))
        obs, _, terminated, _, info = env.step(cmd.action)
        touching.append(info[f"contact_{info['stance_leg']}"])
        swing_down = info[f"contact_{other_leg(info['stance_leg'])}"]
        now = float(env.data.time)
        if info["heel_strikes"] > len(strikes):
            strikes.append(now)
            step_start, swing_lifted = now, False
        elif swing_down and swing_lifted:
            grazes, swing_lifted = grazes + 1, False
        elif not swing_down:
            swing_lifted = True
        if terminated:
            reason = env.healthy.fall_reason(env.data.qpos)
        elif now - step_start > MAX_STEP_FRACTION * duration:
            reason = f"no heel strike within {MAX_STEP_FRACTION:g} step durations"
    last = policy.command(obs, info)
    frames.append((env.data.time, env.state_vector()[: len(JOINTS)], last))
    control_dt = env.dt
    env.close()
    return _result(frames, steps, reason, policy.gains, strikes, control_dt, float(np.mean(touching)), grazes)


def _result(
    frames: list[tuple[float, np.ndarray, Any]],
    steps: int,
    reason: str | None,
    gains: PDGains,
    strikes: list[float],
    control_dt: float,
    stance_contact: float,
    grazes: int,
) -> ClosedLoopResult:
    acted = [cmd for _, _, cmd in frames[:-1]]  # the last frame's decision is never applied
    err = np.array([c.joints_ref - c.joints for c in acted])
    ff = float(sum(np.abs(c.tau_ff).sum() for c in acted))
    fb = float(sum(np.abs(c.tau_fb).sum() for c in acted))
    cmds = [cmd for _, _, cmd in frames]
    return ClosedLoopResult(
        steps_requested=steps,
        steps_walked=len(strikes),
        fall_reason=reason,
        tracking_rms=float(np.sqrt(np.mean(err**2))),
        tracking_max=float(np.abs(err).max()),
        feedback_share=fb / (ff + fb) if ff + fb > 0 else 0.0,
        gains=gains,
        control_dt=control_dt,
        times=np.array([t for t, _, _ in frames]),
        qpos=np.array([q for _, q, _ in frames]),
        stance=np.array([c.stance_leg for c in cmds]),
        phase=np.array([c.phase for c in cmds]),
        joints=np.array([c.joints for c in cmds]),
        joints_ref=np.array([c.joints_ref for c in cmds]),
        tau_ff=np.array([c.tau_ff for c in cmds]),
        tau_fb=np.array([c.tau_fb for c in cmds]),
        heel_strikes=tuple(strikes),
        stance_contact=stance_contact,
        grazes=grazes,
    )


def track_demonstrations(
    demos: Iterable[Demonstration | str | os.PathLike], steps: int = DEFAULT_STEPS, gains: PDGains | None = None
) -> list[ClosedLoopResult]:
    """The closed-loop check of each demonstration (objects or ``.npz`` paths) on its own model."""
    out = []
    for demo in demos:
        if not isinstance(demo, Demonstration):
            demo = Demonstration.load(demo)
        out.append(closed_loop_replay(demo, steps=steps, gains=gains))
    return out
