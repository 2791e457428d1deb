"""The physical verdict on a demonstration: one check per way a gait can be physically wrong.

Each check measures one figure on the demonstration's own trajectory (its knots, as the
optimizer wrote them) and compares it with one limit:

1. ``inverse_dynamics``: MuJoCo's inverse dynamics need the demonstration's torques and
   ground force for its motion (:mod:`envs.checks.inverse_dynamics`); relative residual.
2. ``time_consistency``: the velocities and accelerations integrate to the positions over
   the knot spacing (Hermite-Simpson defects relative to the motion of one interval). The
   inverse dynamics are evaluated knot by knot and never see the spacing; this check does.
3. ``ground_normal_force``: the stance foot's ground force, from MuJoCo's inverse dynamics
   of the motion alone (Newton's law for the whole body: ``F = sum m_i a_i - m g``), never
   pulls: its least normal component, in body weights.
4. ``friction_cone``: the same force stays in the friction cone ``|f_x| <= mu f_z`` of the
   walker's own friction coefficient (``params.friction``): its largest excess
   ``|f_x| - mu f_z``, in body weights.
5. ``swing_penetration``: the swing foot stays at or above the ground (height 0) at
   every knot: its depth below it, in leg lengths (the foot point's, or a rolling arc's
   lowest point's).
6. ``knee_range``: both knees stay within ``[0, knee_max_flexion]`` (0 is straight, where
   the knee-lock holds): the largest excursion beyond, in rad.

Checks 3-6 are inequalities the trajectory optimizer imposes; their limit is
:data:`~ioc_bench.trajopt.solution.FEASIBILITY_TOL`, the constraint violation at which the
benchmark's own solver still accepts a solution (everything is dimensionless: body mass,
gravity and leg length 1). Checks 1 and 2 are equalities with a relative figure; their
limit is :data:`~envs.checks.inverse_dynamics.ID_TOLERANCE` (0.1 %). docs/environment.md,
"The physical checks", says why each limit is what it is; the measurements are in
docs/notes/2026-12-03-physical-checks.md.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import mujoco
import numpy as np

from envs.checks.inverse_dynamics import ID_TOLERANCE, InverseDynamicsResult
from envs.physics import MujocoParams, Physics, check_physics, foot_contact_point, foot_roll
from envs.reference import DemoReference
from ioc_bench.demo import Demonstration
from ioc_bench.model.mjcf import JOINTS, LEGS
from ioc_bench.trajopt.collocation import defects
from ioc_bench.trajopt.solution import FEASIBILITY_TOL

#: Limit of the inequality checks (ground force, friction cone, penetration, knee range):
#: the constraint violation the benchmark's solver accepts (body weights, leg lengths, rad).
INEQUALITY_TOL = FEASIBILITY_TOL
#: Limit of the time-consistency check: relative defect (the inverse dynamics' 0.1 %).
TIMING_TOL = ID_TOLERANCE


@dataclass(frozen=True)
class PhysicsCheck:
    """One physical check: a measured figure against its limit.

    Attributes:
        name: the check's name (``inverse_dynamics``, ``ground_normal_force``, ...).
        value: the measured figure.
        limit: the limit it is compared with.
        sense: ``"<="`` (pass when ``value <= limit``) or ``">="``.
        passed: whether the figure is within the limit.
        quantity: what ``value`` measures, with its unit (one line).
        reason: on failure, one line naming what is physically wrong and where; "" on a pass.
        knot: the knot of the worst figure (None if the figure is not a knot's).
    """

    name: str
    value: float
    limit: float
    sense: str
    passed: bool
    quantity: str
    reason: str = ""
    knot: int | None = None

    def to_dict(self) -> dict[str, Any]:
        return {
            "name": self.name,
            "value": self.value,
            "limit": self.limit,
            "sense": self.sense,
            "passed": self.passed,
            "quantity": self.quantity,
            "reason": self.reason,
            "knot": self.knot,
        }


def _judge(
    name: str, value: float, limit: float, sense: str, quantity: str, why: str, knot: int | None
) -> PhysicsCheck:
    """A check whose reason on failure is ``why`` (the cause, with the figure and the knot)."""
    ok = bool(value <= limit) if sense == "<=" else bool(value >= limit)
    return PhysicsCheck(name, float(value), float(limit), sense, ok, quantity, "" if ok else why, knot)


def inverse_dynamics_verdict(result: InverseDynamicsResult) -> PhysicsCheck:
    """The inverse-dynamics result as a physical check (torques consistent with the dynamics)."""
    why = (
        f"torques inconsistent with the dynamics: residual {result.relative_residual:.2e} of peak torque "
        f"at knot {result.worst_knot} ({result.worst_dof})"
    )
    ok = result.passed
    return PhysicsCheck(
        "inverse_dynamics",
        result.relative_residual,
        result.tolerance,
        "<",
        ok,
        "inverse-dynamics residual / peak torque",
        "" if ok else why,
        result.worst_knot,
    )


def time_consistency_check(demo: Demonstration, tolerance: float = TIMING_TOL) -> PhysicsCheck:
    """Do the segment angles' rates and accelerations integrate to the angles over the knot spacing?

    The Hermite-Simpson defects (Simpson quadrature and Hermite midpoint) of every interval
    of the collocated state (segment angles and angular velocities), divided by the largest
    change of that state over one interval. A motion replayed slower or faster than its
    velocities say (a stretched ``dt``) fails here, not in the knot-wise inverse dynamics.
    """
    ref = DemoReference.of(demo)
    y, f, h = ref.theta, ref.dtheta, 2.0 * ref.dt
    worst, knot, scale = 0.0, 0, 0.0
    for k in range(0, len(ref.times) - 1, 2):
        simpson, hermite = defects(*y[k : k + 3], *f[k : k + 3], h)
        size = max(float(np.abs(simpson).max()), float(np.abs(hermite).max()))
        if size > worst:
            worst, knot = size, k
        scale = max(scale, float(np.abs(y[k + 2] - y[k]).max()))
    value = worst / scale if scale > 0 else 0.0
    why = (
        f"motion inconsistent with its timing: velocities and accelerations do not integrate to the positions "
        f"over dt={ref.dt:.4g} (defect {value:.2e} of one interval's motion, interval from knot {knot})"
    )
    quantity = "Hermite-Simpson defect / largest motion of one interval"
    return _judge("time_consistency", value, tolerance, "<=", quantity, why, knot)


def stance_ground_forces(
    demo: Demonstration, params: MujocoParams | None = None, *, physics: Physics | None = None
) -> np.ndarray:
    """(T, 2) ground force ``(f_x, f_z)`` on the stance foot that the motion needs, knot by knot.

    MuJoCo's inverse dynamics (constraints disabled) of each knot's state and acceleration:
    the root's slide joints ``rootx`` and ``rootz`` carry no actuator, and the stance foot's
    Jacobian on them is the identity, so their generalized forces are the ground force,
    ``sum m_i a_i - m g`` (Newton's law for the whole body). Only the motion and the model
    enter: not the demonstration's torques, nor its own pin forces. ``physics``: the model
    of ``params`` a replay's checks share (None: built here).
    """
    physics = check_physics(physics, params or demo.params)
    model, data = physics.model, physics.data
    ref = DemoReference.of(demo)
    rows = [JOINTS.index("rootx"), JOINTS.index("rootz")]
    forces = np.zeros((len(ref.times), 2))
    for k in range(len(ref.times)):
        data.qpos[:], data.qvel[:], data.qacc[:] = ref.qpos[k], ref.qvel[k], ref.qacc[k]
        mujoco.mj_inverse(model, data)
        forces[k] = data.qfrc_inverse[rows]
    return forces


def ground_force_checks(
    demo: Demonstration,
    params: MujocoParams | None = None,
    tolerance: float = INEQUALITY_TOL,
    *,
    physics: Physics | None = None,
) -> tuple[PhysicsCheck, PhysicsCheck]:
    """The stance foot's ground force: it never pulls, and it stays in the friction cone.

    Figures in body weights ``m g`` of ``params`` (default: the demonstration's own); the
    friction coefficient is ``params.friction``, the one the optimizer and MuJoCo use.
    """
    p = params or demo.params
    weight = p.total_mass * p.gravity
    fx, fz = (stance_ground_forces(demo, p, physics=physics) / weight).T
    k = int(np.argmin(fz))
    pull = _judge(
        "ground_normal_force",
        fz[k],
        -tolerance,
        ">=",
        "least normal ground force on the stance foot / body weight",
        f"ground force pulls the stance foot down: normal force {fz[k]:.3g} m g at knot {k}",
        k,
    )
    excess = np.abs(fx) - p.friction * fz
    j = int(np.argmax(excess))
    cone = _judge(
        "friction_cone",
        excess[j],
        tolerance,
        "<=",
        f"largest |f_x| - mu f_z on the stance foot / body weight (mu {p.friction:g})",
        f"ground force leaves the friction cone: |f_x| = {abs(fx[j]):.3g} m g > mu f_z = "
        f"{p.friction * fz[j]:.3g} m g at knot {j}",
        j,
    )
    return pull, cone


def penetration_check(
    demo: Demonstration,
    params: MujocoParams | None = None,
    tolerance: float = INEQUALITY_TOL,
    *,
    physics: Physics | None = None,
) -> PhysicsCheck:
    """Depth of the swing foot below the ground (height 0) at the knots, in leg lengths.

    MuJoCo's forward kinematics of each knot with leg ``a`` in stance: the swing foot is
    site ``foot_b``, its lowest point a rolling arc's radius below it
    (:func:`envs.physics.foot_contact_point`). Negative values are clearance (the foot's
    least height above ground). ``physics``: the model of ``params`` a replay's checks
    share (None: built here; forward kinematics ignores its disabled constraints).
    """
    p = params or demo.params
    physics = check_physics(physics, p)
    model, data = physics.model, physics.data
    ref, roll = DemoReference.of(demo), foot_roll(p)
    heights = np.zeros(len(ref.times))
    for k in range(len(ref.times)):
        data.qpos[:] = ref.qpos[k]
        mujoco.mj_kinematics(model, data)
        heights[k] = foot_contact_point(model, data, LEGS[1], roll)[2]
    k = int(np.argmin(heights))
    return _judge(
        "swing_penetration",
        -heights[k],
        tolerance,
        "<=",
        "depth of the swing foot below the ground (leg lengths)",
        f"swing foot penetrates the ground: {-heights[k]:.3g} L below it at knot {k}",
        k,
    )


def knee_range_check(
    demo: Demonstration, params: MujocoParams | None = None, tolerance: float = INEQUALITY_TOL
) -> PhysicsCheck:
    """Largest excursion of a knee beyond ``[0, knee_max_flexion]`` (rad).

    Flexion below 0 is a knee bent backwards past straight, where the passive knee-lock
    holds it; beyond ``knee_max_flexion`` the knee is folded past its range.
    """
    p = params or demo.params
    ref = DemoReference.of(demo)
    names = [f"knee_{leg}" for leg in LEGS]
    flexion = ref.qpos[:, [JOINTS.index(n) for n in names]]
    beyond = np.maximum(-flexion, flexion - p.knee_max_flexion)
    k, i = np.unravel_index(int(np.argmax(beyond)), beyond.shape)
    role = "stance" if i == 0 else "swing"
    what = "past straight (knee-lock)" if flexion[k, i] < 0 else f"past its flexion limit {p.knee_max_flexion:g}"
    return _judge(
        "knee_range",
        beyond[k, i],
        tolerance,
        "<=",
        f"largest knee angle beyond [0, {p.knee_max_flexion:g}] rad",
        f"{role} knee beyond its range: flexion {flexion[k, i]:.3g} rad, {beyond[k, i]:.3g} {what}, at knot {k}",
        int(k),
    )


def physics_checks(
    demo: Demonstration,
    inverse_dynamics: InverseDynamicsResult,
    params: MujocoParams | None = None,
    *,
    physics: Physics | None = None,
) -> tuple[PhysicsCheck, ...]:
    """Every physical check of ``demo`` against the model of ``params`` (default: its own).

    ``inverse_dynamics`` is the result of :func:`~envs.checks.inverse_dynamics_check` for
    the same demonstration and model (the report keeps its details). The checks share one
    compiled model, ``physics`` (None: built here, once).
    """
    physics = check_physics(physics, params or demo.params)
    return (
        inverse_dynamics_verdict(inverse_dynamics),
        time_consistency_check(demo),
        *ground_force_checks(demo, params, physics=physics),
        penetration_check(demo, params, physics=physics),
        knee_range_check(demo, params),
    )
