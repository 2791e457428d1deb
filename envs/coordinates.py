"""Segment states (the optimizer's coordinates) <-> MuJoCo's generalized coordinates.

The optimizer describes each segment by ``(x, z, theta)`` and names legs by role
(stance, swing); the MuJoCo model (:mod:`ioc_bench.model.mjcf`) has a floating hip and
relative joint angles, and names legs by side (``a``, ``b``). A step is replayed with one
physical leg in the stance role; at heel strike the roles swap. ``stance`` below is the
physical leg ("a" or "b") in the stance role.

qpos = ``[hip x, hip z, torso angle, hip_a, knee_a, hip_b, knee_b]``, where a hip angle
is ``theta_thigh - theta_torso`` and a knee angle ``theta_shank - theta_thigh`` (flexion).

The walker and the ``rolling-feet`` walker share this layout and their actuators (the
walker's ``ACTUATORS``; :func:`check_actuators`). The root is the hip, read off the
demonstration's segment positions, which place the stance foot where the optimizer's
ground pin holds it: a point foot at the origin, a rolling arc with its contact point
moved along the ground by ``R theta`` (the arc's anchor at the origin).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from ioc_bench.model.linkage import Linkage, point_acceleration, point_offset, point_position, point_velocity
from ioc_bench.model.mjcf import JOINTS, LEGS, MOTORS
from ioc_bench.model.walker import ACTUATORS

#: Role segment names of each physical leg's (thigh, shank), given the stance leg.
_ROLE_SEGMENTS = {"stance": ("thigh_stance", "shank_stance"), "swing": ("thigh_swing", "shank_swing")}
#: qpos index of each physical leg's (hip, knee).
_LEG_DOFS = {leg: (JOINTS.index(f"hip_{leg}"), JOINTS.index(f"knee_{leg}")) for leg in LEGS}


def _role_name(joint: str, stance: str) -> str:
    """``hip_a`` -> ``hip_stance`` when leg a is in stance, ``hip_swing`` otherwise."""
    kind, leg = joint.split("_")
    return f"{kind}_{'stance' if leg == stance else 'swing'}"


#: For each stance leg: index into ``ACTUATORS`` (role order) of each motor, in ``MOTORS`` order.
_MOTOR_FROM_ROLE = {st: [ACTUATORS.index(_role_name(m, st)) for m in MOTORS] for st in LEGS}
#: For each stance leg: qvel index of each role joint, in ``ACTUATORS`` order (motors share joint names).
_DOF_OF_ROLE = {st: [JOINTS.index(MOTORS[_MOTOR_FROM_ROLE[st].index(r)]) for r in range(len(ACTUATORS))] for st in LEGS}


def check_actuators(linkage: Linkage) -> Linkage:
    """Return ``linkage`` if its actuated joints are the MuJoCo motors' (``ACTUATORS``), else
    raise ``ValueError`` (its demonstrations' torques would drive the wrong joints)."""
    names = tuple(j.name for j in linkage.actuated)
    if names != ACTUATORS:
        raise ValueError(f"the MuJoCo models drive the joints {ACTUATORS}; this linkage's actuators are {names}")
    return linkage


def check_stance(stance: str) -> str:
    """Return ``stance`` if it names a leg of the model, else raise ``ValueError``."""
    if stance not in LEGS:
        raise ValueError(f"stance leg must be one of {LEGS}, got {stance!r}")
    return stance


def other_leg(leg: str) -> str:
    """The leg that is not ``leg``: the stance role moves to it at heel strike."""
    return LEGS[1 - LEGS.index(check_stance(leg))]


def leg_roles(stance: str) -> dict[str, str]:
    """Physical leg -> role ("stance" or "swing")."""
    return {stance: "stance", other_leg(stance): "swing"}


def to_generalized(
    linkage: Linkage,
    q: np.ndarray,
    v: np.ndarray,
    acc: np.ndarray | None = None,
    stance: str = "a",
) -> tuple[np.ndarray, np.ndarray, np.ndarray | None]:
    """``(qpos, qvel, qacc)`` of one knot's segment state (``qacc`` is None if ``acc`` is).

    The root is the torso's hip point (position, velocity, acceleration); joint angles and
    their derivatives are differences of segment angles and their derivatives.

    Args:
        linkage: the walker's linkage (segment names in role labels).
        q, v, acc: (S, 3) segment positions, velocities and accelerations.
        stance: the physical leg in the stance role.
    """
    check_stance(stance)
    it = linkage.index("torso")
    torso = linkage.segments[it]
    qpos = _assemble(linkage, point_position(torso, "hip", q[it]), q[:, 2], stance)
    qvel = _assemble(linkage, point_velocity(torso, "hip", q[it], v[it]), v[:, 2], stance)
    if acc is None:
        return qpos, qvel, None
    qacc = _assemble(linkage, point_acceleration(torso, "hip", q[it], v[it], acc[it]), acc[:, 2], stance)
    return qpos, qvel, qacc


def _assemble(linkage: Linkage, root: Sequence[float], theta: np.ndarray, stance: str) -> np.ndarray:
    """Generalized vector from the root point and segment angles (or their derivatives)."""
    it = linkage.index("torso")
    out = np.zeros(7)
    out[0], out[1], out[2] = float(root[0]), float(root[1]), theta[it]
    for leg, role in leg_roles(stance).items():
        thigh, shank = (linkage.index(n) for n in _ROLE_SEGMENTS[role])
        hip, knee = _LEG_DOFS[leg]
        out[hip] = theta[thigh] - theta[it]
        out[knee] = theta[shank] - theta[thigh]
    return out


def to_segments(linkage: Linkage, qpos: np.ndarray, qvel: np.ndarray, stance: str) -> tuple[np.ndarray, np.ndarray]:
    """Inverse of :func:`to_generalized`: (S, 3) segment positions and velocities, role labels."""
    check_stance(stance)
    q = np.zeros((len(linkage.segments), 3))
    v = np.zeros_like(q)
    hip, hip_v = np.asarray(qpos[:2], dtype=float), np.asarray(qvel[:2], dtype=float)
    it = linkage.index("torso")
    _place(linkage, q, v, it, "hip", hip, hip_v, qpos[2], qvel[2])
    for leg, role in leg_roles(stance).items():
        thigh_name, shank_name = _ROLE_SEGMENTS[role]
        i_hip, i_knee = _LEG_DOFS[leg]
        th, th_d = qpos[2] + qpos[i_hip], qvel[2] + qvel[i_hip]
        sh, sh_d = th + qpos[i_knee], th_d + qvel[i_knee]
        ith, ish = linkage.index(thigh_name), linkage.index(shank_name)
        _place(linkage, q, v, ith, "hip", hip, hip_v, th, th_d)
        knee = np.array(point_position(linkage.segments[ith], "knee", q[ith]), dtype=float)
        knee_v = np.array(point_velocity(linkage.segments[ith], "knee", q[ith], v[ith]), dtype=float)
        _place(linkage, q, v, ish, "knee", knee, knee_v, sh, sh_d)
    return q, v


def _place(
    linkage: Linkage,
    q: np.ndarray,
    v: np.ndarray,
    i: int,
    point: str,
    at: np.ndarray,
    at_v: np.ndarray,
    theta: float,
    omega: float,
) -> None:
    """Set segment ``i``'s state so that its ``point`` is at ``at`` moving with ``at_v``."""
    rx, rz = (float(c) for c in point_offset(linkage.segments[i], point, theta))
    q[i] = (at[0] - rx, at[1] - rz, theta)
    v[i] = (at_v[0] - omega * rz, at_v[1] + omega * rx, omega)


def motor_controls(role_torques: Sequence[float] | np.ndarray, stance: str) -> np.ndarray:
    """Motor vector ``(hip_a, hip_b, knee_a, knee_b)`` from torques in ``ACTUATORS`` (role) order.

    Works on (..., 4) arrays.
    """
    return np.asarray(role_torques, dtype=float)[..., _MOTOR_FROM_ROLE[check_stance(stance)]]


def role_torques(motor: Sequence[float] | np.ndarray, stance: str) -> np.ndarray:
    """Inverse of :func:`motor_controls` (the permutation is its own inverse)."""
    return np.asarray(motor, dtype=float)[..., _MOTOR_FROM_ROLE[check_stance(stance)]]


def generalized_torques(role: np.ndarray, stance: str) -> np.ndarray:
    """(7,) generalized forces of joint torques given in ``ACTUATORS`` (role) order."""
    out = np.zeros(7)
    out[_DOF_OF_ROLE[check_stance(stance)]] = role
    return out


def actuated_dofs(stance: str) -> list[int]:
    """qvel indices of the joints ``(hip_stance, hip_swing, knee_stance, knee_swing)``."""
    return list(_DOF_OF_ROLE[check_stance(stance)])
