"""Replay a demonstration in MuJoCo: three independent checks of an optimal gait.

1. **Inverse dynamics** (:func:`inverse_dynamics_check`): MuJoCo's ``mj_inverse`` on every
   knot's state and acceleration, with constraints (contacts, limits) disabled, must give
   the optimizer's joint torques (actuators plus knee-locks) plus the stance foot's ground
   force mapped through the foot Jacobian, ``J_foot^T F_ground``; the root DOFs carry no
   actuator, so their residual must vanish too. Figure of merit:
   ``max |residual| / max |tau|`` over knots and DOFs. Matching models give ~1e-12; a model
   with 10 % heavier legs gives several hundred percent (the demonstrations' torques are
   small, ~0.06 m g L, while a mass error shifts forces by ~0.01 m g).
2. **Open loop** (:func:`open_loop_replay`): simulate the step from its initial state with
   the demonstration's torques, quadratic in each interval as Hermite-Simpson assumes,
   on soft ground, the knee limit acting as the knee-lock. Walking is unstable, so the
   simulation drifts; the final-state error is reported, not judged.
3. **Closed loop** (:func:`closed_loop_replay`): the demonstration torques as feed-forward
   plus joint-space PD tracking of its joint angles, legs swapped at each heel strike and
   the reference restarted. The reference is indexed by the step's **phase**, the hip's
   forward distance from the stance foot (monotonic in every demonstration), rather than
   by the clock: the walker's forward rotation about its foot is unactuated, and a clock
   reference lets it drift into a different gait (measured: steps 60 % longer after five
   steps). Reference joint rates are scaled by the actual over the reference phase rate.
   Reports steps walked, tracking error (RMS and max over physics steps and the four
   actuated joints, rad), and the feedback share
   ``sum |tau_fb| / (sum |tau_ff| + sum |tau_fb|)`` over every physics step and joint.

Legs: the demonstration's stance leg is MuJoCo leg ``a`` in the first step.
"""

from __future__ import annotations

import os
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import mujoco
import numpy as np

from envs.coordinates import actuated_dofs, generalized_torques, motor_controls, other_leg, to_generalized
from envs.physics import HealthyRange, aligned_timestep, build_model, foot_in_contact
from ioc_bench.demo import Demonstration
from ioc_bench.model.linkage import Linkage, point_offset
from ioc_bench.model.mjcf import JOINTS, ContactSettings
from ioc_bench.model.params import WalkerParams
from ioc_bench.model.walker import ACTUATORS, LOCKS, PINS, WALKER_ROLES, walker_linkage
from ioc_bench.trajopt.collocation import interpolate, quadratic

#: Inverse-dynamics residual above which the models are judged different (relative to peak torque).
ID_TOLERANCE = 1e-3
#: Feedback share at or above which the closed loop is judged not to follow the demonstration.
FEEDBACK_SHARE_LIMIT = 0.2
#: Steps the closed loop walks by default.
DEFAULT_STEPS = 10
#: A touchdown counts as heel strike only after this fraction of the reference step.
MIN_STEP_FRACTION = 0.5
#: A step that has not ended after this multiple of the reference duration counts as a fall.
MAX_STEP_FRACTION = 2.0


# -- the demonstration as the replays read it ---------------------------------------------


@dataclass(frozen=True, eq=False)
class Reference:
    """A demonstration in the form the replays use.

    Attributes:
        linkage: the demonstration's linkage.
        times: (T,) knot times.
        theta: (T, 2S) segment angles and angular velocities (the collocated state).
        dtheta: (T, 2S) their time derivatives.
        tau: (T, 4) actuated torques in ``ACTUATORS`` order.
        joint_map: (4, S) actuated joint angles = ``joint_map @ segment angles``.
        qpos, qvel, qacc: (T, 7) MuJoCo coordinates of every knot, leg ``a`` in stance.
    """

    linkage: Linkage
    times: np.ndarray
    theta: np.ndarray
    dtheta: np.ndarray
    tau: np.ndarray
    joint_map: np.ndarray
    qpos: np.ndarray
    qvel: np.ndarray
    qacc: np.ndarray

    @classmethod
    def of(cls, demo: Demonstration) -> Reference:
        link = walker_linkage(demo.params)
        tr = demo.trajectory
        jmap = np.zeros((len(ACTUATORS), len(link.segments)))
        for i, joint in enumerate(link.actuated):
            jmap[i, link.index(joint.child)] += 1.0
            jmap[i, link.index(joint.parent)] -= 1.0
        knots = [to_generalized(link, tr.q[k], tr.v[k], tr.acc[k], "a") for k in range(tr.n_knots)]
        qpos, qvel, qacc = (np.array([kn[i] for kn in knots]) for i in range(3))
        return cls(
            linkage=link,
            times=tr.times,
            theta=np.concatenate([tr.q[:, :, 2], tr.v[:, :, 2]], axis=1),
            dtheta=np.concatenate([tr.v[:, :, 2], tr.acc[:, :, 2]], axis=1),
            tau=tr.tau,
            joint_map=jmap,
            qpos=qpos,
            qvel=qvel,
            qacc=qacc,
        )

    @property
    def duration(self) -> float:
        return float(self.times[-1])

    @property
    def dt(self) -> float:
        return float(self.times[1] - self.times[0])

    def joints(self, t: float) -> tuple[np.ndarray, np.ndarray]:
        """Actuated joint angles and rates (``ACTUATORS`` order) at time ``t``."""
        state, _ = interpolate(self.times, self.theta, self.dtheta, t)
        n = self.joint_map.shape[1]
        return self.joint_map @ state[:n], self.joint_map @ state[n:]

    def torque(self, t: float) -> np.ndarray:
        """Feed-forward torques (``ACTUATORS`` order) at time ``t``, quadratic per interval."""
        return quadratic(self.times, self.tau, t)

    def phase_path(self, per_knot: int = 20) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Fine samples ``(t, x, xdot)`` of the hip's forward distance from the stance foot."""
        tg = np.linspace(0.0, self.duration, per_knot * (len(self.times) - 1) + 1)
        n = self.joint_map.shape[1]
        rows = []
        for t in tg:
            state, _ = interpolate(self.times, self.theta, self.dtheta, t)
            rows.append(_hip_over_foot(self.linkage, state[:n], state[n:]))
        x, xd = np.array(rows).T
        if np.any(np.diff(x) <= 0):
            raise ValueError("the demonstration's hip does not move steadily forward over the stance foot")
        return tg, x, xd


def _hip_over_foot(link: Linkage, theta: np.ndarray, omega: np.ndarray) -> tuple[float, float]:
    """Forward position and velocity of the hip relative to the stance foot, from segment angles."""
    x = xd = 0.0
    for name, (upper, lower) in (("thigh_stance", ("hip", "knee")), ("shank_stance", ("knee", "foot"))):
        i = link.index(name)
        (ux, uz), (lx, lz) = (point_offset(link.segments[i], p, theta[i]) for p in (upper, lower))
        x += float(ux - lx)
        xd += float(omega[i] * (uz - lz))
    return x, xd


# -- 1. inverse dynamics ------------------------------------------------------------------


@dataclass(frozen=True, eq=False)
class InverseDynamicsResult:
    """MuJoCo's inverse dynamics against the optimizer's torques and ground force.

    Attributes:
        residual: (T, 7) ``qfrc_inverse - (joint torques + J_foot^T F_ground)`` per knot and DOF.
        peak_torque: max |actuated torque| of the demonstration.
        max_residual: max |residual|.
        relative_residual: ``max_residual / peak_torque``.
        worst_knot: knot of the largest residual.
        worst_dof: DOF (joint name) of the largest residual.
        tolerance: relative residual at or above which the check fails.
    """

    residual: np.ndarray
    peak_torque: float
    max_residual: float
    relative_residual: float
    worst_knot: int
    worst_dof: str
    tolerance: float = ID_TOLERANCE

    @property
    def passed(self) -> bool:
        return bool(self.relative_residual < self.tolerance)

    def to_dict(self) -> dict[str, Any]:
        return {
            "relative_residual": self.relative_residual,
            "max_residual": self.max_residual,
            "peak_torque": self.peak_torque,
            "worst_knot": self.worst_knot,
            "worst_dof": self.worst_dof,
            "tolerance": self.tolerance,
            "passed": self.passed,
        }


def inverse_dynamics_check(
    demo: Demonstration,
    params: WalkerParams | None = None,
    tolerance: float = ID_TOLERANCE,
) -> InverseDynamicsResult:
    """Compare MuJoCo's inverse dynamics with the demonstration's torques at every knot.

    Args:
        demo: the demonstration.
        params: the model MuJoCo uses (default: the demonstration's own). Another model
            (say the nominal one for a heavy-legs demonstration) must fail the check.
        tolerance: relative residual at or above which the check fails.
    """
    model = build_model(params or demo.params)
    model.opt.disableflags |= mujoco.mjtDisableBit.mjDSBL_CONSTRAINT
    data = mujoco.MjData(model)
    ref, tr = Reference.of(demo), demo.trajectory
    foot = model.site("foot_a").id
    ground = PINS.index(WALKER_ROLES.contact_pin)
    knees = [ACTUATORS.index(n) for n in LOCKS]
    jac = np.zeros((3, model.nv))
    residual = np.zeros((tr.n_knots, model.nv))
    for k in range(tr.n_knots):
        data.qpos[:], data.qvel[:], data.qacc[:] = ref.qpos[k], ref.qvel[k], ref.qacc[k]
        mujoco.mj_inverse(model, data)
        mujoco.mj_jacSite(model, data, jac, None, foot)
        joint = tr.tau[k].copy()
        joint[knees] += tr.lock[k]
        fx, fz = tr.pin_forces[k, ground]
        residual[k] = data.qfrc_inverse - (generalized_torques(joint, "a") + jac[0] * fx + jac[2] * fz)
    peak = float(np.max(np.abs(tr.tau)))
    worst = np.unravel_index(int(np.argmax(np.abs(residual))), residual.shape)
    max_res = float(np.abs(residual).max())
    return InverseDynamicsResult(
        residual=residual,
        peak_torque=peak,
        max_residual=max_res,
        relative_residual=max_res / peak if peak > 0 else float("inf"),
        worst_knot=int(worst[0]),
        worst_dof=JOINTS[int(worst[1])],
        tolerance=tolerance,
    )


# -- 2. open loop -------------------------------------------------------------------------


@dataclass(frozen=True, eq=False)
class OpenLoopResult:
    """The step simulated with the demonstration's torques alone.

    Attributes:
        times: (T,) knot times.
        qpos, qvel: (T, 7) simulated state at each knot time.
        qpos_ref, qvel_ref: (T, 7) the demonstration's state at the knots.
        final_position_error: max |qpos - qpos_ref| at the last knot (leg lengths or rad).
        final_velocity_error: max |qvel - qvel_ref| at the last knot.
        touchdown_time: first time the swing foot touched the floor after half the step
            (None if not before the end).
    """

    times: np.ndarray
    qpos: np.ndarray
    qvel: np.ndarray
    qpos_ref: np.ndarray
    qvel_ref: np.ndarray
    final_position_error: float
    final_velocity_error: float
    touchdown_time: float | None

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
        }


def open_loop_replay(
    demo: Demonstration,
    params: WalkerParams | None = None,
    contact: ContactSettings | None = None,
) -> OpenLoopResult:
    """Simulate one step from the demonstration's initial state with its torques alone."""
    ref = Reference.of(demo)
    model = build_model(params or demo.params, contact)
    per_knot = aligned_timestep(model, ref.dt)
    data = mujoco.MjData(model)
    data.qpos[:], data.qvel[:] = ref.qpos[0], ref.qvel[0]
    mujoco.mj_forward(model, data)
    qpos, qvel, touchdown = [data.qpos.copy()], [data.qvel.copy()], None
    for k in range(1, len(ref.times)):
        for i in range(per_knot):
            t = ref.times[k - 1] + i * model.opt.timestep
            data.ctrl[:] = motor_controls(ref.torque(t), "a")
            mujoco.mj_step(model, data)
            if touchdown is None and t > MIN_STEP_FRACTION * ref.duration and foot_in_contact(model, data, "b"):
                touchdown = float(t + model.opt.timestep)
        qpos.append(data.qpos.copy())
        qvel.append(data.qvel.copy())
    qpos_a, qvel_a = np.array(qpos), np.array(qvel)
    return OpenLoopResult(
        times=ref.times,
        qpos=qpos_a,
        qvel=qvel_a,
        qpos_ref=ref.qpos,
        qvel_ref=ref.qvel,
        final_position_error=float(np.abs(qpos_a[-1] - ref.qpos[-1]).max()),
        final_velocity_error=float(np.abs(qvel_a[-1] - ref.qvel[-1]).max()),
        touchdown_time=touchdown,
    )


# -- 3. closed loop -----------------------------------------------------------------------


@dataclass(frozen=True)
class PDGains:
    """Joint-space PD gains, the same for the four actuated joints.

    The defaults were picked on nominal-weight steps at speed 0.27 (1 and 15 starts, and
    the +10 % leg-mass walker) from kp in {2, 3, 4} and kd in {0.1, 0.15, 0.2}: every pair
    walks 10 steps with a feedback share of 9-16 %; (3, 0.15) also walks the fast (0.34)
    step for 10 steps, where the share is much higher (~80 %).

    Attributes:
        kp: stiffness (torque per rad, units m g L).
        kd: damping (torque per rad per time unit).
    """

    kp: float = 3.0
    kd: float = 0.15


@dataclass(frozen=True, eq=False)
class ClosedLoopResult:
    """The gait repeated under feed-forward plus PD tracking.

    Attributes:
        steps_requested: steps the replay tried to walk.
        steps_walked: heel strikes reached before a fall (or the end).
        fall_reason: why the walk stopped early (None if it walked every step).
        tracking_rms: RMS joint-angle error over all physics steps and actuated joints (rad).
        tracking_max: max |joint-angle error| (rad).
        feedback_share: ``sum |tau_fb| / (sum |tau_ff| + sum |tau_fb|)``.
        gains: the PD gains used.
        times: (N,) times of the recorded frames (one per knot spacing).
        qpos: (N, 7) recorded states.
        stance: (N,) the stance leg ("a" or "b") at each frame.
        phase: (N,) reference time (phase) at each frame.
        joints: (N, 4) actual actuated joint angles, ``ACTUATORS`` (role) order.
        joints_ref: (N, 4) their reference.
        tau_ff, tau_fb: (N, 4) feed-forward and feedback torques, ``ACTUATORS`` order.
        heel_strikes: times of the heel strikes.
        share_limit: feedback share at or above which the check fails.
    """

    steps_requested: int
    steps_walked: int
    fall_reason: str | None
    tracking_rms: float
    tracking_max: float
    feedback_share: float
    gains: PDGains
    times: np.ndarray
    qpos: np.ndarray
    stance: np.ndarray
    phase: np.ndarray
    joints: np.ndarray
    joints_ref: np.ndarray
    tau_ff: np.ndarray
    tau_fb: np.ndarray
    heel_strikes: tuple[float, ...]
    share_limit: float = FEEDBACK_SHARE_LIMIT

    @property
    def passed(self) -> bool:
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
            "step_durations": np.diff((0.0, *self.heel_strikes)).tolist(),
            "distance": float(self.qpos[-1, 0] - self.qpos[0, 0]),
            "passed": self.passed,
        }


@dataclass
class _Tally:
    """Running sums and recorded frames of the closed loop."""

    err2: float = 0.0
    err_max: float = 0.0
    count: int = 0
    ff: float = 0.0
    fb: float = 0.0
    frames: list[tuple[Any, ...]] = field(default_factory=list)

    def add(self, err: np.ndarray, ff: np.ndarray, fb: np.ndarray) -> None:
        self.err2 += float(err @ err)
        self.err_max = max(self.err_max, float(np.abs(err).max()))
        self.count += len(err)
        self.ff += float(np.abs(ff).sum())
        self.fb += float(np.abs(fb).sum())


class _Tracker:
    """Feed-forward plus joint-space PD on the phase-indexed reference, one physics step at a time."""

    def __init__(self, ref: Reference, gains: PDGains, model: mujoco.MjModel):
        self.ref, self.gains, self.model = ref, gains, model
        self.path_t, self.path_x, self.path_xd = ref.phase_path()
        self.feet = {leg: model.site(f"foot_{leg}").id for leg in ("a", "b")}

    def phase(self, data: mujoco.MjData, stance: str) -> tuple[float, float]:
        """Reference time matching the hip's distance from the stance foot, and the phase rate."""
        foot_x = data.site_xpos[self.feet[stance]][0]
        t = float(np.interp(data.qpos[0] - foot_x, self.path_x, self.path_t))
        return t, float(data.qvel[0]) / float(np.interp(t, self.path_t, self.path_xd))

    def control(self, data: mujoco.MjData, stance: str) -> tuple[float, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """``(phase, q, q_ref, tau_ff, tau_fb)``, joint quantities in ``ACTUATORS`` order."""
        t, rate = self.phase(data, stance)
        dofs = actuated_dofs(stance)
        q_ref, qd_ref = self.ref.joints(t)
        q, qd = data.qpos[dofs], data.qvel[dofs]
        fb = self.gains.kp * (q_ref - q) + self.gains.kd * (rate * qd_ref - qd)
        return t, q.copy(), q_ref, self.ref.torque(t), fb


def closed_loop_replay(
    demo: Demonstration,
    steps: int = DEFAULT_STEPS,
    gains: PDGains | None = None,
    params: WalkerParams | None = None,
    healthy: HealthyRange | None = None,
    contact: ContactSettings | None = None,
) -> ClosedLoopResult:
    """Walk ``steps`` steps: demonstration torques plus joint-space PD, legs swapped at heel strike.

    A heel strike is the swing foot touching the floor after it has left it, past
    :data:`MIN_STEP_FRACTION` of the reference step. The walk stops early on a fall
    (``healthy``) or when a step lasts over :data:`MAX_STEP_FRACTION` reference durations.

    Args:
        demo: the demonstration; its initial state starts the walk with leg ``a`` in stance.
        steps: heel strikes to reach.
        gains: PD gains (default :class:`PDGains`).
        params: the MuJoCo model (default: the demonstration's own).
        healthy: fall criterion (default :class:`HealthyRange`).
        contact: contact settings of the MuJoCo model.
    """
    gains, healthy, ref = gains or PDGains(), healthy or HealthyRange(), Reference.of(demo)
    model = build_model(params or demo.params, contact)
    per_knot = aligned_timestep(model, ref.dt)
    data = mujoco.MjData(model)
    data.qpos[:], data.qvel[:] = ref.qpos[0], ref.qvel[0]
    mujoco.mj_forward(model, data)
    tracker, tally = _Tracker(ref, gains, model), _Tally()
    stance, step_start, lifted, strikes, reason, i = "a", 0.0, False, [], None, 0
    while len(strikes) < steps and reason is None:
        phase, q, q_ref, ff, fb = tracker.control(data, stance)
        if i % per_knot == 0:
            tally.frames.append((data.time, data.qpos.copy(), stance, phase, q, q_ref, ff, fb))
        tally.add(q_ref - q, ff, fb)
        data.ctrl[:] = motor_controls(ff + fb, stance)
        mujoco.mj_step(model, data)
        i += 1
        swing = other_leg(stance)
        touching = foot_in_contact(model, data, swing)
        lifted = lifted or not touching
        reason = healthy.fall_reason(data.qpos)
        if reason is None and data.time - step_start > MAX_STEP_FRACTION * ref.duration:
            reason = f"no heel strike within {MAX_STEP_FRACTION:g} step durations"
        if reason is None and touching and lifted and phase > MIN_STEP_FRACTION * ref.duration:
            strikes.append(float(data.time))
            stance, step_start, lifted = swing, float(data.time), False
    phase, q, q_ref, ff, _ = tracker.control(data, stance)
    tally.frames.append((data.time, data.qpos.copy(), stance, phase, q, q_ref, ff, np.zeros(4)))
    return _closed_loop_result(tally, steps, reason, gains, strikes)


def _closed_loop_result(
    tally: _Tally, steps: int, reason: str | None, gains: PDGains, strikes: list[float]
) -> ClosedLoopResult:
    times, qpos, stance, phase, q, q_ref, ff, fb = (np.array(x) for x in zip(*tally.frames))
    total = tally.ff + tally.fb
    return ClosedLoopResult(
        steps_requested=steps,
        steps_walked=len(strikes),
        fall_reason=reason,
        tracking_rms=float(np.sqrt(tally.err2 / max(tally.count, 1))),
        tracking_max=tally.err_max,
        feedback_share=tally.fb / total if total > 0 else 0.0,
        gains=gains,
        times=times,
        qpos=qpos,
        stance=stance,
        phase=phase,
        joints=q,
        joints_ref=q_ref,
        tau_ff=ff,
        tau_fb=fb,
        heel_strikes=tuple(strikes),
    )


# -- all three, and what they write -------------------------------------------------------


@dataclass(frozen=True, eq=False)
class ReplayReport:
    """The three checks of one demonstration against one MuJoCo model."""

    inverse_dynamics: InverseDynamicsResult
    open_loop: OpenLoopResult
    closed_loop: ClosedLoopResult

    @property
    def passed(self) -> bool:
        """Inverse dynamics and closed loop pass (the open loop is reported, not judged)."""
        return self.inverse_dynamics.passed and self.closed_loop.passed

    def to_dict(self) -> dict[str, Any]:
        return {
            "inverse_dynamics": self.inverse_dynamics.to_dict(),
            "open_loop": self.open_loop.to_dict(),
            "closed_loop": self.closed_loop.to_dict(),
            "passed": self.passed,
        }


def replay(
    demo: Demonstration,
    steps: int = DEFAULT_STEPS,
    params: WalkerParams | None = None,
    gains: PDGains | None = None,
) -> ReplayReport:
    """Run the three checks of ``demo`` against the MuJoCo model of ``params`` (default: its own)."""
    return ReplayReport(
        inverse_dynamics=inverse_dynamics_check(demo, params),
        open_loop=open_loop_replay(demo, params),
        closed_loop=closed_loop_replay(demo, steps, gains, params),
    )


def write_animation(
    closed: ClosedLoopResult,
    params: WalkerParams,
    path: str | os.PathLike,
    fps: float = 20.0,
    speed: float = 1.0,
) -> Path:
    """GIF of the closed-loop walk (stick figure), ``speed`` time units per second of GIF."""
    from envs.drawing import StickRenderer, write_gif

    renderer = StickRenderer(params, 320, 240)
    step = max(1, round(speed / fps / float(np.median(np.diff(closed.times)))))
    strikes = np.asarray(closed.heel_strikes)
    frames = [
        renderer.render(qpos, f"t = {t:5.2f}   step {int(np.sum(strikes <= t)) + 1}")
        for t, qpos in zip(closed.times[::step], closed.qpos[::step])
    ]
    renderer.close()
    return write_gif(path, frames, fps)


def plot_comparison(
    demo: Demonstration,
    open_loop: OpenLoopResult,
    closed: ClosedLoopResult,
    path: str | os.PathLike,
) -> Path:
    """Joint angles and torques: demonstration vs MuJoCo open loop vs every closed-loop step."""
    from ioc_bench.viz.common import plt, save_figure

    ref = Reference.of(demo)
    fig, axes = plt.subplots(3, 2, figsize=(10, 9))
    dofs = actuated_dofs("a")
    demo_q = np.column_stack([ref.qpos[:, 2], ref.qpos[:, dofs]])
    open_q = np.column_stack([open_loop.qpos[:, 2], open_loop.qpos[:, dofs]])
    closed_q = np.column_stack([closed.qpos[:, 2], closed.joints])
    starts = np.flatnonzero(np.r_[True, closed.stance[1:] != closed.stance[:-1]])
    for j, (ax, name) in enumerate(zip(axes.ravel()[:5], ("torso", *ACTUATORS))):
        for s, e in zip(starts, [*starts[1:], len(closed.times)]):
            ax.plot(closed.phase[s:e], closed_q[s:e, j], color="tab:blue", lw=0.8, alpha=0.6)
        ax.plot(ref.times, open_q[:, j], "--", color="tab:orange", lw=1.2)
        ax.plot(ref.times, demo_q[:, j], color="black", lw=2)
        ax.set_ylabel(f"{name.replace('_', ' ')} angle (rad)")
    axes[0, 0].plot([], [], color="black", lw=2, label="demonstration")
    axes[0, 0].plot([], [], "--", color="tab:orange", label="MuJoCo open loop")
    axes[0, 0].plot([], [], color="tab:blue", lw=0.8, label="MuJoCo closed loop, each step")
    axes[0, 0].legend(fontsize=7)
    ax = axes[2, 1]
    ax.plot(closed.times, np.abs(closed.tau_ff).sum(axis=1), color="black", lw=1, label="|feed-forward|")
    ax.plot(closed.times, np.abs(closed.tau_fb).sum(axis=1), color="tab:red", lw=1, label="|feedback|")
    ax.set_ylabel("|torque| summed over joints (m g L)")
    ax.set_xlabel("closed-loop time (sqrt(L/g))")
    ax.legend(fontsize=7)
    axes[2, 0].set_xlabel("step phase (demonstration time, sqrt(L/g))")
    fig.suptitle(
        f"MuJoCo replay: open-loop final error {open_loop.final_position_error:.3g}; "
        f"closed loop {closed.steps_walked}/{closed.steps_requested} steps, "
        f"feedback share {100 * closed.feedback_share:.1f} %",
        fontsize=10,
    )
    return save_figure(fig, path)


__all__ = [
    "ClosedLoopResult",
    "InverseDynamicsResult",
    "OpenLoopResult",
    "PDGains",
    "Reference",
    "ReplayReport",
    "closed_loop_replay",
    "inverse_dynamics_check",
    "open_loop_replay",
    "plot_comparison",
    "replay",
    "write_animation",
]
