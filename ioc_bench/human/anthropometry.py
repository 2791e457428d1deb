"""The subject's walker: segment lengths from the standing trial, masses and inertias from Winter.

The walker's leg is a thigh (hip to knee) and a shank that carries the foot and ends in a
point foot on the floor below the ankle. From the static markers (lab axes X forward, Y up,
Z right, mm):

- hip joint centre by the regression of Harrington et al. (2007, J Biomech 40:595-602)
  from the pelvis width (ASIS to ASIS) and depth (mid-ASIS to mid-PSIS);
- knee and ankle centres as midpoints of the lateral and medial epicondyle and malleolus
  markers; the ankle height is the ankle centre above the floor (Y = 0);
- thigh = hip to knee centre, shank = knee to ankle centre, each the mean of both sides;
  the walker's leg length L = thigh + shank + ankle height (the standing leg, straight).

Masses, centres of mass and radii of gyration are Winter's (2009, *Biomechanics and Motor
Control of Human Movement*, 4th ed., Table 4.1, after Dempster), the table the default
walker was scaled from (docs/spec.md, "Segment parameters"): HAT 0.678, thigh 0.100, leg 0.0465 and foot 0.0145
of the body mass. The torso (head, arms and trunk) length is hip to shoulder, 0.288 of
body height (Winter's Figure 4.1, after Drillis & Contini: shoulder 0.818 H, greater
trochanter 0.530 H), because WBDS has no trunk markers. The foot is a mass at Winter's
foot centre of mass (midway from the ankle centre to the second metatarsal marker),
projected on the leg's axis at its height above the floor.

Everything is returned in the walker's units: leg length 1, body mass 1.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ioc_bench.features import PAPER_GRAVITY
from ioc_bench.human.wbds import StaticMarkers, TableRow, WbdsDataError
from ioc_bench.model.params import SegmentParams, WalkerParams
from ioc_bench.model.winter import HAT_LENGTH, WINTER

#: Plausible range (m) of each leg segment length; outside it the markers are refused.
SEGMENT_RANGE = (0.2, 0.7)
#: Plausible range (m) of the ankle centre's height above the floor.
ANKLE_HEIGHT_RANGE = (0.02, 0.2)


@dataclass(frozen=True)
class BodyLengths:
    """Lengths of the subject's leg from the standing trial, metres (mean of both sides).

    Attributes:
        thigh: hip joint centre to knee centre.
        shank: knee centre to ankle centre.
        ankle_height: ankle centre above the floor.
        foot: ankle centre to the second metatarsal marker (Winter's foot length).
        foot_com_height: height of the foot's centre of mass above the floor.
        side_difference: largest right-left difference of thigh or shank, m.
    """

    thigh: float
    shank: float
    ankle_height: float
    foot: float
    foot_com_height: float
    side_difference: float

    @property
    def leg_length(self) -> float:
        """Hip joint centre to floor along the straight leg: the walker's unit of length."""
        return self.thigh + self.shank + self.ankle_height


@dataclass(frozen=True)
class SubjectBody:
    """A subject's body as the walker sees it.

    Attributes:
        lengths: leg lengths from the standing trial.
        height: body height, m (the table's).
        mass: body mass as listed, kg (the table's; forces are normalised by the measured
            weight instead, see :mod:`ioc_bench.human.step`).
        gender: ``M`` or ``F``.
    """

    lengths: BodyLengths
    height: float
    mass: float
    gender: str

    @property
    def leg_length(self) -> float:
        return self.lengths.leg_length

    @property
    def time_unit(self) -> float:
        """Seconds per walker time unit, sqrt(L / g)."""
        return math.sqrt(self.leg_length / PAPER_GRAVITY)

    @property
    def speed_unit(self) -> float:
        """Metres per second per walker speed unit, sqrt(g L)."""
        return math.sqrt(PAPER_GRAVITY * self.leg_length)

    def walker(self) -> WalkerParams:
        """The subject's walker (see :func:`subject_walker`)."""
        return subject_walker(self.lengths, self.height)


def hip_joint_centres(static: StaticMarkers) -> dict[str, np.ndarray]:
    """Right and left hip joint centres (mm, lab axes) by Harrington et al. (2007)."""
    r_asis, l_asis = static["R.ASIS"], static["L.ASIS"]
    mid_asis = (r_asis + l_asis) / 2
    mid_psis = (static["R.PSIS"] + static["L.PSIS"]) / 2
    width = float(np.linalg.norm(r_asis - l_asis))
    depth = float(np.linalg.norm(mid_asis - mid_psis))
    if width < 1 or depth < 1:
        raise WbdsDataError(f"{static.path.name}: the pelvis markers coincide (ASIS or PSIS)")
    right = (r_asis - l_asis) / width
    forward = mid_asis - mid_psis
    forward = forward - right * (forward @ right)
    forward /= np.linalg.norm(forward)
    up = np.cross(right, forward)
    out = {}
    for side, sign in (("R", 1.0), ("L", -1.0)):
        out[side] = (
            mid_asis
            + forward * (-0.24 * depth - 9.9)
            + up * (-0.30 * width - 10.9)
            + right * sign * (0.33 * width + 7.3)
        )
    return out


def body_lengths(static: StaticMarkers) -> BodyLengths:
    """The leg's lengths from a standing trial; refuses implausible markers with one line."""
    hips = hip_joint_centres(static)
    per_side = {}
    for side in "RL":
        knee = (static[f"{side}.Knee"] + static[f"{side}.Knee.Medial"]) / 2
        ankle = (static[f"{side}.Ankle"] + static[f"{side}.Ankle.Medial"]) / 2
        toe = static[f"{side}.MT2"]
        per_side[side] = (
            float(np.linalg.norm(hips[side] - knee)),
            float(np.linalg.norm(knee - ankle)),
            float(ankle[1]),
            float(np.linalg.norm(toe - ankle)),
            float((ankle[1] + toe[1]) / 2),
        )
        if not hips[side][1] > knee[1] > ankle[1]:
            raise WbdsDataError(f"{static.path.name}: {side} hip, knee and ankle centres are not one above the other")
    mean = np.mean([per_side["R"], per_side["L"]], axis=0) / 1000.0
    thigh, shank, ankle_height, foot, foot_com = (float(x) for x in mean)
    for name, value, (lo, hi) in (
        ("thigh", thigh, SEGMENT_RANGE),
        ("shank", shank, SEGMENT_RANGE),
        ("ankle height", ankle_height, ANKLE_HEIGHT_RANGE),
    ):
        if not lo <= value <= hi:
            raise WbdsDataError(f"{static.path.name}: {name} {value:.3f} m is outside {lo}-{hi} m")
    diff = max(abs(per_side["R"][k] - per_side["L"][k]) for k in (0, 1)) / 1000.0
    return BodyLengths(thigh, shank, ankle_height, foot, foot_com, diff)


def subject_body(static: StaticMarkers, row: TableRow) -> SubjectBody:
    """The subject's body from the standing trial and the table's height and mass."""
    return SubjectBody(body_lengths(static), row.height, row.mass, row.gender)


def subject_walker(lengths: BodyLengths, height: float) -> WalkerParams:
    """The walker of a subject with these leg lengths and body height, in walker units.

    Lengths are divided by the leg length L, masses are Winter's fractions (they sum to 1),
    inertias are ``mass * (gyration * length)^2`` in units of body mass times L^2. The
    shank segment is Winter's leg plus foot (see the module docstring). Friction, torque
    bound and knee range are the default walker's.
    """
    leg = lengths.leg_length
    if not (math.isfinite(height) and height > leg):
        raise ValueError(f"body height {height!r} m must exceed the leg length {leg:.3f} m")
    w = WINTER
    thigh_len = lengths.thigh / leg
    thigh = SegmentParams(
        thigh_len, w["thigh"].mass, w["thigh"].com * thigh_len, w["thigh"].mass * (w["thigh"].gyration * thigh_len) ** 2
    )
    shank = _shank_with_foot(lengths, leg)
    hat_len = HAT_LENGTH * height / leg
    hat = w["hat"]
    torso = SegmentParams(hat_len, hat.mass, hat.com * hat_len, hat.mass * (hat.gyration * hat_len) ** 2)
    return WalkerParams(torso=torso, thigh=thigh, shank=shank)


def _shank_with_foot(lengths: BodyLengths, leg: float) -> SegmentParams:
    """Winter's leg (knee to ankle) and foot as one stick from the knee to the floor."""
    w_leg, w_foot = WINTER["leg"], WINTER["foot"]
    shank_len = lengths.shank / leg
    length = (lengths.shank + lengths.ankle_height) / leg
    leg_com = w_leg.com * shank_len
    foot_com = (lengths.shank + lengths.ankle_height - lengths.foot_com_height) / leg
    mass = w_leg.mass + w_foot.mass
    com = (w_leg.mass * leg_com + w_foot.mass * foot_com) / mass
    inertia = (
        w_leg.mass * (w_leg.gyration * shank_len) ** 2
        + w_leg.mass * (leg_com - com) ** 2
        + w_foot.mass * (w_foot.gyration * lengths.foot / leg) ** 2
        + w_foot.mass * (foot_com - com) ** 2
    )
    return SegmentParams(length, mass, com, inertia)
