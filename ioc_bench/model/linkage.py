"""A general planar linkage: rigid segments joined by pins, driven by joint torques.

This is the description the trajectory optimizer transcribes (the paper's segment-based
formulation): each segment has its own planar state, each pin its own constraint force.
A different planar linkage (say, with ankles) is a new :class:`Linkage`, not new code.

A point may carry a rolling arc (:attr:`Segment.rolls`): the point is the arc's centre and
a pin from it to the world rolls the arc on the ground without slipping instead of holding
the point (a foot that rolls). With no arcs every expression is that of plain pins.

Conventions (shared with the MuJoCo model): x forward, z up. A segment's angle ``theta``
is its rotation about +y, so its axis ``u = (sin theta, cos theta)`` leans forward for
positive theta. A joint's angle is ``theta_child - theta_parent``; a joint torque acts
``+tau`` on the child and ``-tau`` on the parent. Planar moments are about +y:
``r x F = r_z F_x - r_x F_z``.

The numeric values in a linkage may be CasADi symbols: :meth:`Linkage.with_parameters`
swaps them for a parameter vector so one compiled NLP serves every model variant.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field, replace
from typing import Any

import casadi as ca

Point = tuple[Any, Any]


@dataclass(frozen=True)
class Segment:
    """A rigid segment.

    Attributes:
        name: unique name.
        mass: mass.
        inertia: moment of inertia about the centre of mass.
        points: named points as (along, across) offsets from the centre of mass, in the
            segment frame: ``along`` follows the axis ``u``, ``across`` follows
            ``n = (cos theta, -sin theta)``.
        rolls: radius of the rolling arc centred at some of the points (a foot that rolls);
            a world pin to such a point rolls (see :func:`ground_gap`).
    """

    name: str
    mass: Any
    inertia: Any
    points: Mapping[str, Point]
    rolls: Mapping[str, Any] = field(default_factory=dict)


@dataclass(frozen=True)
class Pin:
    """A pin joint between a point of segment ``a`` and a point of ``b`` (or the world).

    The pin's constraint force ``[fx, fz]`` acts on ``a``; its reaction acts on ``b``.
    ``b=None`` pins ``a`` to the fixed world point ``b_point`` (coordinates).
    """

    name: str
    a: str
    a_point: str
    b: str | None
    b_point: str | Point


@dataclass(frozen=True)
class Joint:
    """The relative rotation at a pin, ``theta_child - theta_parent``.

    Attributes:
        actuated: a torque actuator drives this joint.
        lock: a passive unilateral lock at angle 0 keeps the angle >= 0 (the knee-lock); its
            range is ``[0, lock_range]`` (the model parameters' ``lock_range``).
        range: ``(low, high)`` angle limits of a joint without a lock (a hard limit that
            the actuator, not a passive element, must respect); None: unlimited.
    """

    name: str
    parent: str
    child: str
    actuated: bool = True
    lock: bool = False
    range: tuple[float, float] | None = None


@dataclass(frozen=True)
class Linkage:
    """Segments, pins and joints of a planar linkage under gravity (-z)."""

    segments: tuple[Segment, ...]
    pins: tuple[Pin, ...]
    joints: tuple[Joint, ...]
    gravity: Any = 1.0

    def __post_init__(self) -> None:
        names = [s.name for s in self.segments]
        if len(set(names)) != len(names):
            raise ValueError(f"duplicate segment names in {names}")
        for pin in self.pins:
            self._check_point(pin.a, pin.a_point, pin.name)
            if pin.b is not None:
                self._check_point(pin.b, pin.b_point, pin.name)
        for joint in self.joints:
            for seg in (joint.parent, joint.child):
                if seg not in names:
                    raise ValueError(f"joint {joint.name!r} names unknown segment {seg!r}")
            if joint.range is not None and (joint.lock or not joint.range[0] < joint.range[1]):
                raise ValueError(f"joint {joint.name!r}: a range needs low < high and no lock, got {joint.range}")
        for seg in self.segments:
            unknown = set(seg.rolls) - set(seg.points)
            if unknown:
                raise ValueError(f"segment {seg.name!r}: rolling arcs at unknown points {sorted(unknown)}")

    def _check_point(self, segment: str, point: Any, where: str) -> None:
        seg = self.segment(segment)
        if point not in seg.points:
            raise ValueError(f"pin {where!r}: segment {segment!r} has no point {point!r}")

    def segment(self, name: str) -> Segment:
        for seg in self.segments:
            if seg.name == name:
                return seg
        raise KeyError(f"no segment named {name!r}")

    def index(self, segment: str) -> int:
        return [s.name for s in self.segments].index(segment)

    def pin_index(self, pin: str) -> int:
        return [p.name for p in self.pins].index(pin)

    @property
    def actuated(self) -> tuple[Joint, ...]:
        return tuple(j for j in self.joints if j.actuated)

    @property
    def locked(self) -> tuple[Joint, ...]:
        return tuple(j for j in self.joints if j.lock)

    @property
    def limited(self) -> tuple[Joint, ...]:
        """Joints with a hard range and no lock."""
        return tuple(j for j in self.joints if j.range is not None)

    # -- parameters -------------------------------------------------------------------
    def parameter_vector(self) -> list[Any]:
        """Every numeric value of the linkage, in a fixed order (see :meth:`with_parameters`)."""
        values: list[Any] = [self.gravity]
        for seg in self.segments:
            values += [seg.mass, seg.inertia]
            for along, across in seg.points.values():
                values += [along, across]
            values += list(seg.rolls.values())
        return values

    def with_parameters(self, values: Sequence[Any]) -> Linkage:
        """The same linkage with its numbers replaced by ``values`` (e.g. CasADi symbols)."""
        it = iter(values)
        gravity = next(it)
        segments = []
        for seg in self.segments:
            mass, inertia = next(it), next(it)
            points = {name: (next(it), next(it)) for name in seg.points}
            rolls = {name: next(it) for name in seg.rolls}
            segments.append(replace(seg, mass=mass, inertia=inertia, points=points, rolls=rolls))
        return replace(self, segments=tuple(segments), gravity=gravity)


# -- kinematics and dynamics, valid for numbers and CasADi expressions alike --------------


def axes(theta: Any) -> tuple[Point, Point]:
    """The segment's axis ``u`` and its perpendicular ``n`` at angle ``theta``."""
    s, c = ca.sin(theta), ca.cos(theta)
    return (s, c), (c, -s)


def point_offset(segment: Segment, point: str, theta: Any) -> Point:
    """World-frame vector from the segment's centre of mass to one of its points."""
    along, across = segment.points[point]
    (ux, uz), (nx, nz) = axes(theta)
    return along * ux + across * nx, along * uz + across * nz


def point_position(segment: Segment, point: str, q: Sequence[Any]) -> Point:
    """Position of a segment point given the segment's ``q = (x, z, theta)``."""
    rx, rz = point_offset(segment, point, q[2])
    return q[0] + rx, q[1] + rz


def point_velocity(segment: Segment, point: str, q: Sequence[Any], v: Sequence[Any]) -> Point:
    """Velocity of a segment point given ``q`` and ``v = (xdot, zdot, thetadot)``."""
    rx, rz = point_offset(segment, point, q[2])
    return v[0] + v[2] * rz, v[1] - v[2] * rx


def moment(r: Point, f: Point) -> Any:
    """Planar moment about +y of force ``f`` applied at offset ``r``."""
    return r[1] * f[0] - r[0] * f[1]


def pin_wrenches(linkage: Linkage, q: Sequence[Sequence[Any]], forces: Sequence[Point]) -> list[list[Any]]:
    """Net force and moment ``[Fx, Fz, M]`` on each segment from the pin forces (or impulses)."""
    wrench: list[list[Any]] = [[0, 0, 0] for _ in linkage.segments]
    for pin, f in zip(linkage.pins, forces):
        for seg_name, point, sign in ((pin.a, pin.a_point, 1), (pin.b, pin.b_point, -1)):
            if seg_name is None:
                continue
            i = linkage.index(seg_name)
            offset = contact_offset if pin.b is None else point_offset
            r = offset(linkage.segments[i], point, q[i][2])
            wrench[i][0] += sign * f[0]
            wrench[i][1] += sign * f[1]
            wrench[i][2] += sign * moment(r, f)
    return wrench


def joint_moments(linkage: Linkage, torques: Mapping[str, Any]) -> list[Any]:
    """Net moment on each segment from joint torques (actuators and locks), by joint name."""
    out: list[Any] = [0 for _ in linkage.segments]
    for joint in linkage.joints:
        tau = torques.get(joint.name, 0)
        out[linkage.index(joint.child)] += tau
        out[linkage.index(joint.parent)] -= tau
    return out


def accelerations(
    linkage: Linkage,
    q: Sequence[Sequence[Any]],
    forces: Sequence[Point],
    torques: Mapping[str, Any],
) -> list[list[Any]]:
    """Newton-Euler per segment: ``[xddot, zddot, thetaddot]`` of each segment.

    Each segment's mass matrix is diagonal, so Newton-Euler is solved in closed form.
    """
    wrench = pin_wrenches(linkage, q, forces)
    moments = joint_moments(linkage, torques)
    acc = []
    for seg, w, m in zip(linkage.segments, wrench, moments):
        acc.append([w[0] / seg.mass, w[1] / seg.mass - linkage.gravity, (w[2] + m) / seg.inertia])
    return acc


def joint_angle(linkage: Linkage, joint: Joint, theta: Sequence[Any]) -> Any:
    return theta[linkage.index(joint.child)] - theta[linkage.index(joint.parent)]


def contact_offset(segment: Segment, point: str, theta: Any) -> Point:
    """World-frame vector from the centre of mass to where ``point`` meets the ground: the
    point itself, or the bottom of its rolling arc."""
    rx, rz = point_offset(segment, point, theta)
    if point not in segment.rolls:
        return rx, rz
    return rx, rz - segment.rolls[point]


def ground_gap(segment: Segment, point: str, q: Sequence[Any]) -> Point:
    """Where ``point`` stands against the ground: its position, or for a rolling arc the
    arc's *anchor*, ``(x_c - R theta, z_c - R)`` with ``(x_c, z_c)`` its centre.

    Rolling without slip moves the arc's centre ``R`` forward per radian of rotation, so
    the anchor stays put while the arc rolls on the ground, and its height is the arc's
    lowest point above the ground. A world pin holds the anchor.
    """
    cx, cz = point_position(segment, point, q)
    if point not in segment.rolls:
        return cx, cz
    radius = segment.rolls[point]
    return cx - radius * q[2], cz - radius


def ground_gap_rate(segment: Segment, point: str, q: Sequence[Any], v: Sequence[Any]) -> Point:
    """Time derivative of :func:`ground_gap` (the rolling arc's slip and lift rates)."""
    vx, vz = point_velocity(segment, point, q, v)
    if point not in segment.rolls:
        return vx, vz
    return vx - segment.rolls[point] * v[2], vz


def ground_gap_acceleration(
    segment: Segment, point: str, q: Sequence[Any], v: Sequence[Any], a: Sequence[Any]
) -> Point:
    """Second time derivative of :func:`ground_gap`."""
    ax, az = point_acceleration(segment, point, q, v, a)
    if point not in segment.rolls:
        return ax, az
    return ax - segment.rolls[point] * a[2], az


def pin_gap(linkage: Linkage, pin: Pin, q: Sequence[Sequence[Any]]) -> Point:
    """Position of the pin's ``a`` point minus that of its ``b`` point (zero when joined);
    a world pin holds :func:`ground_gap` (the point, or a rolling arc's anchor)."""
    if pin.b is None:
        pa = ground_gap(linkage.segment(pin.a), pin.a_point, q[linkage.index(pin.a)])
        return pa[0] - pin.b_point[0], pa[1] - pin.b_point[1]
    pa = point_position(linkage.segment(pin.a), pin.a_point, q[linkage.index(pin.a)])
    pb = point_position(linkage.segment(pin.b), pin.b_point, q[linkage.index(pin.b)])
    return pa[0] - pb[0], pa[1] - pb[1]


def pin_gap_rate(linkage: Linkage, pin: Pin, q: Sequence[Sequence[Any]], v: Sequence[Sequence[Any]]) -> Point:
    """Time derivative of :func:`pin_gap`."""
    ia = linkage.index(pin.a)
    if pin.b is None:
        return ground_gap_rate(linkage.segment(pin.a), pin.a_point, q[ia], v[ia])
    va = point_velocity(linkage.segment(pin.a), pin.a_point, q[ia], v[ia])
    ib = linkage.index(pin.b)
    vb = point_velocity(linkage.segment(pin.b), pin.b_point, q[ib], v[ib])
    return va[0] - vb[0], va[1] - vb[1]


def place(linkage: Linkage, theta: Sequence[float]) -> list[list[float]]:
    """Segment positions ``(x, z, theta)`` that join every pin, given segment angles.

    Starts from the pins to the world and walks the pin graph, so it suits any tree-shaped
    linkage with at least one world pin.
    """
    q: dict[int, list[float]] = {}
    for pin in linkage.pins:
        if pin.b is None:
            i = linkage.index(pin.a)
            seg = linkage.segments[i]
            rx, rz = point_offset(seg, pin.a_point, theta[i])
            radius = seg.rolls.get(pin.a_point, 0.0)  # a rolling arc's centre: anchor + (R theta, R)
            q[i] = [pin.b_point[0] + radius * theta[i] - rx, pin.b_point[1] + radius - rz, theta[i]]
    while len(q) < len(linkage.segments):
        progress = False
        for pin in linkage.pins:
            if pin.b is None:
                continue
            ia, ib = linkage.index(pin.a), linkage.index(pin.b)
            for known, new, kp, np_ in ((ia, ib, pin.a_point, pin.b_point), (ib, ia, pin.b_point, pin.a_point)):
                if known in q and new not in q:
                    px, pz = point_position(linkage.segments[known], kp, q[known])
                    rx, rz = point_offset(linkage.segments[new], np_, theta[new])
                    q[new] = [px - rx, pz - rz, theta[new]]
                    progress = True
        if not progress:
            raise ValueError("linkage is not connected to the world through its pins")
    return [q[i] for i in range(len(linkage.segments))]


def point_acceleration(segment: Segment, point: str, q: Sequence[Any], v: Sequence[Any], a: Sequence[Any]) -> Point:
    """Acceleration of a segment point given the segment's ``q``, ``v`` and ``a``."""
    rx, rz = point_offset(segment, point, q[2])
    w2 = v[2] * v[2]
    return a[0] + a[2] * rz - w2 * rx, a[1] - a[2] * rx - w2 * rz


def pin_gap_acceleration(
    linkage: Linkage,
    pin: Pin,
    q: Sequence[Sequence[Any]],
    v: Sequence[Sequence[Any]],
    a: Sequence[Sequence[Any]],
) -> Point:
    """Second time derivative of :func:`pin_gap`."""
    ia = linkage.index(pin.a)
    if pin.b is None:
        return ground_gap_acceleration(linkage.segment(pin.a), pin.a_point, q[ia], v[ia], a[ia])
    aa = point_acceleration(linkage.segment(pin.a), pin.a_point, q[ia], v[ia], a[ia])
    ib = linkage.index(pin.b)
    ab = point_acceleration(linkage.segment(pin.b), pin.b_point, q[ib], v[ib], a[ib])
    return aa[0] - ab[0], aa[1] - ab[1]
