"""Walkers with feet: the 5-segment walker with rolling feet, or with feet on actuated ankles.

Three descriptions of one family, measured against people in ``docs/feet.md`` (which says
what the catalogue holds of them, and why):

- ``knee="free"``: the knee-lock is optional. A free knee keeps its range ``[0,
  knee_max_flexion]`` as a hard limit, but no passive element holds it straight: the knee
  actuator pays for a straight stance knee, so a flexed one can be cheaper.
- ``foot="roll"``: each shank ends in a rolling arc (radius ``roll_radius``, its lowest
  point the shank's end when the shank is vertical). The stance arc rolls on the ground
  without slipping, the ground force acting at its lowest point; the contact point moves
  forward along the arc as the shank turns, as a person's centre of pressure moves from
  heel to toe (a roll-over shape).
- ``foot="ankle"``: each shank ends at an ankle joint (actuated, within ``ankle_range``)
  carrying a foot segment whose sole is a rolling arc (a rocker sole) under the ankle. The
  foot's angle is free of the shank's, driven by an ankle torque.

Everything goes through :mod:`ioc_bench.model.linkage` (rolling arcs are world pins to
points with :attr:`Segment.rolls`) and the general step problem; nothing here is a code
path of the optimizer. Parameters come from Winter's table (:func:`footed_params`), the
same the subject's walker is built from.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass, field, fields, replace
from typing import Any

from ioc_bench.model.gait_model import GaitModel, GaitRoles, kneed_guess_angles
from ioc_bench.model.linkage import Joint, Linkage, Pin, Segment
from ioc_bench.model.params import SegmentParams
from ioc_bench.model.winter import HAT_LENGTH, WINTER

#: Foot kinds: a point foot (the paper's), a rolling arc at the shank's end, a foot on an ankle.
FOOT_KINDS = ("point", "roll", "ankle")
#: Knee kinds: with the passive lock (the paper's) or free (hard range only).
KNEE_KINDS = ("lock", "free")


@dataclass(frozen=True)
class FootParams:
    """One foot on an ankle, in the foot's neutral pose (sole level, ankle above it).

    Attributes:
        mass: foot mass (body masses).
        inertia: about its centre of mass.
        ankle_height: ankle centre above the sole's lowest point, leg lengths.
        com_forward, com_height: centre of mass ahead of and above the sole point below the ankle.
        sole_forward: lowest point of the sole arc ahead of the point below the ankle.
    """

    mass: float
    inertia: float
    ankle_height: float
    com_forward: float
    com_height: float
    sole_forward: float

    def __post_init__(self) -> None:
        for f in fields(self):
            value = getattr(self, f.name)
            if not (isinstance(value, (int, float)) and math.isfinite(value)):
                raise ValueError(f"foot {f.name} must be a finite number, got {value!r}")
        for name in ("mass", "inertia", "ankle_height"):
            if not getattr(self, name) > 0:
                raise ValueError(f"foot {name} must be positive, got {getattr(self, name)!r}")


#: The reference body of the default parameters, metres: thigh, shank (knee to ankle),
#: ankle height, foot (ankle to the second metatarsal), body height. The mean of the
#: shipped subjects' standing trials, rounded to 5 mm.
REFERENCE_BODY = {"thigh": 0.405, "shank": 0.41, "ankle_height": 0.075, "foot": 0.155, "height": 1.73}
#: Rolling radius of a foot over the leg length: roll-over shapes of people walking are
#: arcs of about 0.3 leg lengths (Hansen, Childress & Knox 2004, J Biomech 37:1467).
ROLL_RADIUS = 0.3
#: Ankle range (foot angle minus shank angle; positive lifts the toe... with the walker's
#: sign of angles, negative lifts the toe), rad.
ANKLE_RANGE = (-0.6, 0.6)


@dataclass(frozen=True)
class FootedParams:
    """Parameters of a walker with feet (defaults: :data:`REFERENCE_BODY` through Winter).

    The default segments are ``footed_params(**REFERENCE_BODY)``'s, whose shank reaches the
    floor; a foot on an ankle on that body is ``footed_params(**REFERENCE_BODY, feet="ankle")``.

    Attributes:
        torso, thigh: as the walker's.
        shank: knee to the floor (``foot="point"`` or ``"roll"``: it carries the foot's mass)
            or knee to the ankle (``foot="ankle"``).
        foot: the foot on the ankle (used by ``foot="ankle"`` only).
        roll_radius: radius of the rolling arc (shank end or sole), leg lengths.
        friction, max_torque, knee_max_flexion, gravity: as the walker's.
        ankle_range: ``(low, high)`` ankle angle (foot minus shank), rad.
    """

    torso: SegmentParams = field(default_factory=lambda: _reference().torso)
    thigh: SegmentParams = field(default_factory=lambda: _reference().thigh)
    shank: SegmentParams = field(default_factory=lambda: _reference().shank)
    foot: FootParams = field(default_factory=lambda: _reference().foot)
    feet: str = "roll"
    knee: str = "free"
    roll_radius: float = ROLL_RADIUS
    friction: float = 1.0
    max_torque: float = 1.0
    knee_max_flexion: float = 2.5
    gravity: float = 1.0
    ankle_range: tuple[float, float] = ANKLE_RANGE

    def __post_init__(self) -> None:
        if self.feet not in FOOT_KINDS or self.knee not in KNEE_KINDS:
            raise ValueError(
                f"feet must be one of {FOOT_KINDS} and knee one of {KNEE_KINDS}, got {self.feet!r}, {self.knee!r}"
            )
        for name in ("roll_radius", "friction", "max_torque", "knee_max_flexion", "gravity"):
            value = getattr(self, name)
            if not (isinstance(value, (int, float)) and math.isfinite(value) and value > 0):
                raise ValueError(f"{name} must be a positive finite number, got {value!r}")
        lo, hi = self.ankle_range
        if not (math.isfinite(lo) and math.isfinite(hi) and lo < hi):
            raise ValueError(f"ankle_range must be (low, high) with low < high, got {self.ankle_range!r}")

    @property
    def total_mass(self) -> float:
        return self.torso.mass + 2 * (self.thigh.mass + self.shank.mass + self._foot_mass)

    @property
    def _foot_mass(self) -> float:
        return self.foot.mass if self.feet == "ankle" else 0.0

    @property
    def leg_length(self) -> float:
        """Hip to floor, straight leg (with a foot on an ankle: thigh, shank and ankle height)."""
        ankle = self.foot.ankle_height if self.feet == "ankle" else 0.0
        return self.thigh.length + self.shank.length + ankle

    @property
    def lock_range(self) -> float:
        return self.knee_max_flexion

    def with_leg_mass_scale(self, factor: float) -> FootedParams:
        """Every leg segment's mass and inertia scaled, the torso keeping the total."""
        legs = self.thigh.mass + self.shank.mass + self._foot_mass
        torso_mass = self.torso.mass - (factor - 1.0) * 2 * legs
        if torso_mass <= 0:
            raise ValueError(f"leg mass factor {factor} leaves no mass for the torso")
        scale = lambda s: replace(s, mass=s.mass * factor, inertia=s.inertia * factor)  # noqa: E731
        return replace(
            self,
            thigh=scale(self.thigh),
            shank=scale(self.shank),
            foot=scale(self.foot),
            torso=replace(self.torso, mass=torso_mass, inertia=self.torso.inertia * torso_mass / self.torso.mass),
        )

    def to_dict(self) -> dict[str, Any]:
        return asdict(self)

    @classmethod
    def from_dict(cls, data: dict[str, Any]) -> FootedParams:
        """Inverse of :meth:`to_dict`; raises ``ValueError`` naming a bad or missing key."""
        try:
            segments = {k: SegmentParams(**data[k]) for k in ("torso", "thigh", "shank")}
            foot = FootParams(**data["foot"])
            scalars = {k: v for k, v in data.items() if k not in (*segments, "foot")}
            scalars["ankle_range"] = tuple(float(v) for v in scalars.get("ankle_range", ANKLE_RANGE))
            scalars = {k: v if k in ("ankle_range", "feet", "knee") else float(v) for k, v in scalars.items()}
            return cls(**segments, foot=foot, **scalars)
        except (KeyError, TypeError) as exc:
            raise ValueError(f"invalid footed-walker parameters: {exc}") from exc


def footed_params(
    thigh: float,
    shank: float,
    ankle_height: float,
    foot: float,
    height: float,
    feet: str = "roll",
    knee: str = "free",
) -> FootedParams:
    """A walker with feet for a body of these lengths (metres), in walker units (leg 1, mass 1).

    Masses, centres of mass and radii of gyration are Winter's (the table of the subject's
    walker). With ``feet="ankle"`` the shank ends at the ankle and the foot is its own
    segment; otherwise the shank carries the foot to the floor, as the subject's walker's
    does. The foot's centre of mass is midway from the ankle to the second metatarsal
    (Winter), placed half a foot ahead of the ankle at half its height; the sole arc's
    lowest point is a quarter foot ahead of the ankle.
    """
    w, hat_length = WINTER, HAT_LENGTH
    leg = thigh + shank + ankle_height
    if not (math.isfinite(height) and height > leg > 0):
        raise ValueError(f"body height {height!r} m must exceed the leg length {leg:.3f} m")

    def stick(row: str, length: float) -> SegmentParams:
        r = w[row]
        return SegmentParams(length, r.mass, r.com * length, r.mass * (r.gyration * length) ** 2)

    f = w["foot"]
    foot_len = foot / leg
    foot_params = FootParams(
        mass=f.mass,
        inertia=f.mass * (f.gyration * foot_len) ** 2,
        ankle_height=ankle_height / leg,
        com_forward=0.5 * foot_len,
        com_height=0.5 * ankle_height / leg,
        sole_forward=0.25 * foot_len,
    )
    shank_seg = stick("leg", shank / leg)
    if feet != "ankle":
        shank_seg = _shank_to_floor(shank_seg, foot_params, (shank + ankle_height) / leg)
    return FootedParams(
        torso=stick("hat", hat_length * height / leg),
        thigh=stick("thigh", thigh / leg),
        shank=shank_seg,
        foot=foot_params,
        feet=feet,
        knee=knee,
    )


def _reference() -> FootedParams:
    """The default parameters: :data:`REFERENCE_BODY` through Winter's table."""
    return footed_params(**REFERENCE_BODY)


def _shank_to_floor(shank: SegmentParams, foot: FootParams, length: float) -> SegmentParams:
    """The shank and its foot as one stick from the knee to the floor (the subject's walker's
    shank): the foot a mass on the axis at its centre-of-mass height."""
    foot_com = length - foot.com_height
    mass = shank.mass + foot.mass
    com = (shank.mass * shank.com + foot.mass * foot_com) / mass
    inertia = shank.inertia + shank.mass * (shank.com - com) ** 2 + foot.inertia + foot.mass * (foot_com - com) ** 2
    return SegmentParams(length, mass, com, inertia)


def from_walker(walker: Any, feet: str, knee: str) -> FootedParams:
    """A walker's own torso, thigh and shank (knee to floor) with feet and knee of these kinds;
    ``feet`` must be ``"point"`` or ``"roll"`` (a walker's shank carries its foot)."""
    if feet == "ankle":
        raise ValueError("a walker's shank reaches the floor; a foot on an ankle needs footed_params")
    return FootedParams(
        torso=walker.torso,
        thigh=walker.thigh,
        shank=walker.shank,
        feet=feet,
        knee=knee,
        friction=walker.friction,
        max_torque=walker.max_torque,
        knee_max_flexion=walker.knee_max_flexion,
        gravity=walker.gravity,
    )


def _stick(name: str, seg: SegmentParams, proximal: str, distal: str, up: bool = False) -> Segment:
    if up:  # torso: proximal end (hip) at the bottom
        return Segment(name, seg.mass, seg.inertia, {proximal: (-seg.com, 0.0), distal: (seg.length - seg.com, 0.0)})
    return Segment(name, seg.mass, seg.inertia, {proximal: (seg.com, 0.0), distal: (seg.com - seg.length, 0.0)})


def _shank(name: str, p: FootedParams) -> Segment:
    """The shank; with ``feet="roll"`` its end is the lowest point of an arc of ``roll_radius``."""
    sh = p.shank
    if p.feet != "roll":
        return _stick(name, sh, "knee", "ankle" if p.feet == "ankle" else "foot")
    centre = sh.com - sh.length + p.roll_radius
    return Segment(name, sh.mass, sh.inertia, {"knee": (sh.com, 0.0), "foot": (centre, 0.0)}, {"foot": p.roll_radius})


def _foot(name: str, p: FootedParams) -> Segment:
    """The foot: axis vertical in the neutral pose, ``across`` forward; the sole arc's centre
    one radius above its lowest point."""
    f = p.foot
    ankle = (f.ankle_height - f.com_height, -f.com_forward)
    sole = (p.roll_radius - f.com_height, f.sole_forward - f.com_forward)
    return Segment(name, f.mass, f.inertia, {"ankle": ankle, "foot": sole}, {"foot": p.roll_radius})


def footed_linkage(params: FootedParams | None = None) -> Linkage:
    """The walker with feet as a planar linkage, the stance foot held by the ground pin."""
    p = params or FootedParams()
    segments = [_stick("torso", p.torso, "hip", "shoulder", up=True)]
    for role in ("stance", "swing"):
        segments += [_stick(f"thigh_{role}", p.thigh, "hip", "knee"), _shank(f"shank_{role}", p)]
        if p.feet == "ankle":
            segments.append(_foot(f"foot_{role}", p))
    pins = [Pin(f"hip_{r}", f"thigh_{r}", "hip", "torso", "hip") for r in ("stance", "swing")]
    pins += [Pin(f"knee_{r}", f"shank_{r}", "knee", f"thigh_{r}", "knee") for r in ("stance", "swing")]
    if p.feet == "ankle":
        pins += [Pin(f"ankle_{r}", f"foot_{r}", "ankle", f"shank_{r}", "ankle") for r in ("stance", "swing")]
    pins.append(Pin("ground", _foot_segment(p, "stance"), "foot", None, (0.0, 0.0)))
    joints = [Joint(f"hip_{r}", "torso", f"thigh_{r}") for r in ("stance", "swing")]
    lock = p.knee == "lock"
    knee_range = None if lock else (0.0, p.knee_max_flexion)
    joints += [Joint(f"knee_{r}", f"thigh_{r}", f"shank_{r}", lock=lock, range=knee_range) for r in ("stance", "swing")]
    if p.feet == "ankle":
        joints += [Joint(f"ankle_{r}", f"shank_{r}", f"foot_{r}", range=p.ankle_range) for r in ("stance", "swing")]
    return Linkage(tuple(segments), tuple(pins), tuple(joints), gravity=p.gravity)


def _foot_segment(p: FootedParams, role: str) -> str:
    return f"foot_{role}" if p.feet == "ankle" else f"shank_{role}"


def footed_roles(feet: str) -> GaitRoles:
    """Who does what in a step: the walker's roles, plus the feet and ankles that swap."""
    foot = {r: ("foot_" if feet == "ankle" else "shank_") + r for r in ("stance", "swing")}
    segments = [("thigh_stance", "thigh_swing"), ("shank_stance", "shank_swing")]
    joints = [("hip_stance", "hip_swing"), ("knee_stance", "knee_swing")]
    if feet == "ankle":
        segments.append(("foot_stance", "foot_swing"))
        joints.append(("ankle_stance", "ankle_swing"))
    return GaitRoles(
        contact_pin="ground",
        swing_foot=(foot["swing"], "foot"),
        stance_foot=(foot["stance"], "foot"),
        swap_segments=tuple(segments),
        swap_joints=tuple(joints),
        torso="torso",
    )


def footed_model(name: str, params: FootedParams) -> GaitModel:
    """A :class:`GaitModel` of the walker with feet of ``params``' kinds (cost groups: hip,
    knee and, with ankles, ankle)."""
    groups = {"hip": ("hip_stance", "hip_swing"), "knee": ("knee_stance", "knee_swing")}
    if params.feet == "ankle":
        groups["ankle"] = ("ankle_stance", "ankle_swing")
    return GaitModel(
        name=name,
        linkage=footed_linkage,
        default_params=params,
        params_from_dict=FootedParams.from_dict,
        roles=footed_roles(params.feet),
        actuator_groups=groups,
        guess_angles=kneed_guess_angles,
    )


#: The catalogue's walker with rolling feet and a free knee (``docs/feet.md`` says why).
ROLLING_FEET = footed_model("rolling-feet", FootedParams())
#: The catalogue's walker with feet on actuated ankles and a free knee, on the same reference
#: body through Winter's table. Built by :func:`footed_params`, not ``FootedParams(feet="ankle")``,
#: whose default shank reaches the floor (it carries the foot, as the rolling-feet walker's does).
ANKLE_FEET = footed_model("ankle-feet", footed_params(**REFERENCE_BODY, feet="ankle", knee="free"))
