"""The walker's physical parameters: the single source of truth (``docs/spec.md``, "The walker").

Everything is dimensionless: leg length 1, total body mass 1, gravity 1, so the time unit
is sqrt(L/g). The trajectory optimizer, the features and the MuJoCo model are all built
from a :class:`WalkerParams`; a model variant (e.g. heavier legs) is a new instance, never
new code.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass, field, fields, replace
from typing import Any


@dataclass(frozen=True)
class SegmentParams:
    """One rigid segment, a stick along its own axis.

    Attributes:
        length: proximal-to-distal length (torso: hip to shoulder).
        mass: segment mass (fraction of body mass).
        com: distance of the centre of mass from the proximal joint (torso: from the hip).
        inertia: moment of inertia about the centre of mass.
    """

    length: float
    mass: float
    com: float
    inertia: float

    def __post_init__(self) -> None:
        for f in fields(self):
            value = getattr(self, f.name)
            if not (isinstance(value, (int, float)) and math.isfinite(value) and value > 0):
                raise ValueError(f"segment {f.name} must be a positive finite number, got {value!r}")
        if self.com >= self.length:
            raise ValueError(f"segment com ({self.com}) must lie within its length ({self.length})")


@dataclass(frozen=True)
class WalkerParams:
    """Parameters of the 5-segment planar walker (defaults: ``docs/spec.md``, "Segment parameters").

    Attributes:
        torso: torso segment; its proximal end is the hip.
        thigh: each thigh; proximal end the hip, distal end the knee.
        shank: each shank with its foot; proximal end the knee, distal end a point foot.
        friction: ground friction coefficient, |horizontal| <= friction * vertical.
        max_torque: bound on each actuated joint torque (units of m g L).
        knee_max_flexion: knee flexion range is [0, knee_max_flexion] rad; 0 is full
            extension, where the passive knee-lock acts.
        gravity: gravitational acceleration (1 in dimensionless units).
    """

    torso: SegmentParams = field(default_factory=lambda: SegmentParams(0.55, 0.678, 0.30, 0.050))
    thigh: SegmentParams = field(default_factory=lambda: SegmentParams(0.46, 0.100, 0.20, 0.0022))
    shank: SegmentParams = field(default_factory=lambda: SegmentParams(0.54, 0.061, 0.25, 0.0016))
    friction: float = 1.0
    max_torque: float = 1.0
    knee_max_flexion: float = 2.5
    gravity: float = 1.0

    def __post_init__(self) -> None:
        for name in ("friction", "max_torque", "knee_max_flexion", "gravity"):
            value = getattr(self, name)
            if not (isinstance(value, (int, float)) and math.isfinite(value) and value > 0):
                raise ValueError(f"{name} must be a positive finite number, got {value!r}")

    @property
    def total_mass(self) -> float:
        return self.torso.mass + 2 * (self.thigh.mass + self.shank.mass)

    @property
    def leg_length(self) -> float:
        return self.thigh.length + self.shank.length

    @property
    def lock_range(self) -> float:
        """Range of the locked joints (the knees): flexion in [0, lock_range]."""
        return self.knee_max_flexion

    def with_leg_mass_scale(self, factor: float) -> WalkerParams:
        """A variant with every leg segment's mass scaled by ``factor``.

        Leg inertias scale with their mass (same geometry, denser material). The torso
        gives up the added mass so the total stays unchanged, and its inertia scales with
        its mass too. The ``mass`` condition (``docs/spec.md``, "Conditions") is ``with_leg_mass_scale(1.1)``.
        """
        added = (factor - 1.0) * 2 * (self.thigh.mass + self.shank.mass)
        torso_mass = self.torso.mass - added
        if torso_mass <= 0:
            raise ValueError(f"leg mass factor {factor} leaves no mass for the torso")
        return replace(
            self,
            thigh=replace(self.thigh, mass=self.thigh.mass * factor, inertia=self.thigh.inertia * factor),
            shank=replace(self.shank, mass=self.shank.mass * factor, inertia=self.shank.inertia * factor),
            torso=replace(
                self.torso,
                mass=torso_mass,
                inertia=self.torso.inertia * torso_mass / self.torso.mass,
            ),
        )

    def to_dict(self) -> dict[str, Any]:
        return asdict(self)

    @classmethod
    def from_dict(cls, data: dict[str, Any]) -> WalkerParams:
        """Inverse of :meth:`to_dict`; raises ``ValueError`` naming a bad or missing key."""
        try:
            segments = {k: SegmentParams(**data[k]) for k in ("torso", "thigh", "shank")}
            scalars = {k: float(v) for k, v in data.items() if k not in segments}
            return cls(**segments, **scalars)
        except (KeyError, TypeError) as exc:
            raise ValueError(f"invalid walker parameters: {exc}") from exc


def _leg_as_one(thigh: SegmentParams, shank: SegmentParams) -> SegmentParams:
    """A rigid leg with the mass, centre of mass and inertia of a straight thigh and shank."""
    mass = thigh.mass + shank.mass
    com_shank = thigh.length + shank.com
    com = (thigh.mass * thigh.com + shank.mass * com_shank) / mass
    inertia = thigh.inertia + thigh.mass * (com - thigh.com) ** 2 + shank.inertia + shank.mass * (com_shank - com) ** 2
    return SegmentParams(thigh.length + shank.length, mass, com, inertia)


@dataclass(frozen=True)
class CompassParams:
    """Parameters of the compass walker with a torso: rigid legs, no knees.

    Defaults: the 5-segment walker's torso, and legs that are its thigh and shank fused
    straight (same mass, centre of mass and inertia), so the two models walk alike.

    Attributes:
        torso: torso segment; its proximal end is the hip.
        leg: each leg, hip to point foot.
        friction, max_torque, gravity: as in :class:`WalkerParams`.
    """

    torso: SegmentParams = field(default_factory=lambda: WalkerParams().torso)
    leg: SegmentParams = field(default_factory=lambda: _leg_as_one(WalkerParams().thigh, WalkerParams().shank))
    friction: float = 1.0
    max_torque: float = 1.0
    gravity: float = 1.0

    def __post_init__(self) -> None:
        for name in ("friction", "max_torque", "gravity"):
            value = getattr(self, name)
            if not (isinstance(value, (int, float)) and math.isfinite(value) and value > 0):
                raise ValueError(f"{name} must be a positive finite number, got {value!r}")

    @property
    def total_mass(self) -> float:
        return self.torso.mass + 2 * self.leg.mass

    @property
    def leg_length(self) -> float:
        return self.leg.length

    @property
    def lock_range(self) -> float:
        """No joint has a lock; the value is unused."""
        return 0.0

    def with_leg_mass_scale(self, factor: float) -> CompassParams:
        """A variant with both legs' mass (and inertia) scaled by ``factor``, the torso giving
        up the added mass (as :meth:`WalkerParams.with_leg_mass_scale` does for thighs and shanks)."""
        added = (factor - 1.0) * 2 * self.leg.mass
        torso_mass = self.torso.mass - added
        if torso_mass <= 0:
            raise ValueError(f"leg mass factor {factor} leaves no mass for the torso")
        return replace(
            self,
            leg=replace(self.leg, mass=self.leg.mass * factor, inertia=self.leg.inertia * factor),
            torso=replace(self.torso, mass=torso_mass, inertia=self.torso.inertia * torso_mass / self.torso.mass),
        )

    def to_dict(self) -> dict[str, Any]:
        return asdict(self)

    @classmethod
    def from_dict(cls, data: dict[str, Any]) -> CompassParams:
        """Inverse of :meth:`to_dict`; raises ``ValueError`` naming a bad or missing key."""
        try:
            segments = {k: SegmentParams(**data[k]) for k in ("torso", "leg")}
            scalars = {k: float(v) for k, v in data.items() if k not in segments}
            return cls(**segments, **scalars)
        except (KeyError, TypeError) as exc:
            raise ValueError(f"invalid compass-walker parameters: {exc}") from exc
