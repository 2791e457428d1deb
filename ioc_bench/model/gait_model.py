"""What the trajectory optimizer needs to know about a walking linkage, as one description.

A :class:`GaitModel` names a planar linkage (built from its parameters), the roles its parts
play in a step (which foot is pinned, which lands, what swaps at heel strike), how its
actuators group into cost features, and a rough picture of how it walks (the optimizer's
first guess). The 5-segment walker and the compass walker are two such descriptions; the
optimizer, the features and the demonstrations take any of them.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass
from typing import Any, Protocol

import numpy as np

from ioc_bench.model.linkage import Linkage


class GaitParams(Protocol):
    """Model parameters the optimizer reads besides the linkage's own numbers."""

    friction: float
    max_torque: float
    gravity: float

    @property
    def lock_range(self) -> float:
        """Largest angle of a joint with a passive lock (0 is where the lock acts)."""
        ...

    @property
    def leg_length(self) -> float: ...

    @property
    def total_mass(self) -> float: ...

    def to_dict(self) -> dict[str, Any]: ...

    def with_leg_mass_scale(self, factor: float) -> Any:
        """The same model with every leg segment's mass scaled, the torso keeping the total."""
        ...


@dataclass(frozen=True)
class GaitRoles:
    """What each part does in a step, for a linkage that walks by swapping two legs.

    Attributes:
        contact_pin: the pin holding the stance foot to the ground (at the world origin).
        swing_foot: (segment, point) of the foot that lands at the end of the step.
        stance_foot: (segment, point) of the foot on the ground during the step.
        swap_segments: pairs of segments exchanged at heel strike.
        swap_joints: pairs of joints exchanged at heel strike.
        torso: the segment whose angle the torso feature measures.
    """

    contact_pin: str
    swing_foot: tuple[str, str]
    stance_foot: tuple[str, str]
    swap_segments: tuple[tuple[str, str], ...]
    swap_joints: tuple[tuple[str, str], ...]
    torso: str


@dataclass(frozen=True)
class GuessShape:
    """The few numbers that shape a rough step (step length, torso lean, knee flexions)."""

    step: float = 0.4
    lean: float = 0.05
    knee_swing: float = 0.5
    knee_stance: float = 0.0


@dataclass(frozen=True, eq=False)
class GaitModel:
    """A walking linkage as the optimizer sees it.

    Attributes:
        name: unique name (stored with every demonstration).
        linkage: builds the linkage from parameters (numbers or CasADi symbols).
        default_params: the model's nominal parameters.
        params_from_dict: inverse of the parameters' ``to_dict``.
        roles: what each part does in a step.
        actuator_groups: cost-feature groups of actuated joints, e.g. ``{"hip": (...)}``.
        guess_angles: ``(linkage, params, shape, phases) -> (n, S)`` segment angles of a
            rough step at phases in [0, 1] (kinematics only; the optimizer does the rest).
    """

    name: str
    linkage: Callable[[Any], Linkage]
    default_params: Any
    params_from_dict: Callable[[Mapping[str, Any]], Any]
    roles: GaitRoles
    actuator_groups: Mapping[str, tuple[str, ...]]
    guess_angles: Callable[[Linkage, Any, GuessShape, np.ndarray], np.ndarray]

    def __post_init__(self) -> None:
        link = self.linkage(self.default_params)
        actuated = {j.name for j in link.actuated}
        for group, joints in self.actuator_groups.items():
            unknown = set(joints) - actuated
            if unknown:
                raise ValueError(f"model {self.name!r}: group {group!r} names non-actuated joints {sorted(unknown)}")


def permutation(names: tuple[str, ...], pairs: tuple[tuple[str, str], ...]) -> list[int]:
    """Index permutation swapping each pair: ``names[perm[i]]`` is the partner of ``names[i]``."""
    partner = dict(pairs) | {b: a for a, b in pairs}
    return [names.index(partner.get(n, n)) for n in names]


def stance_swing_angles(step: float, leg_length: float, s: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Leg angles of an inverted-pendulum stance and a mirror-wise swing, and a mid-swing bump."""
    beta = np.arcsin(np.clip(step / (2 * leg_length), -1, 1))
    return -beta + 2 * beta * s, beta - 2 * beta * s, np.sin(np.pi * s)


def kneed_guess_angles(linkage: Linkage, params: Any, shape: GuessShape, s: np.ndarray) -> np.ndarray:
    """The rough step of a walker with a torso, thighs and shanks (named as the walker's):
    straight stance leg rotating, swing leg mirror-wise with a mid-swing knee bend, torso
    leaning, every other segment (feet) level. ``params`` needs only ``leg_length``."""
    stance, swing, bump = stance_swing_angles(shape.step, params.leg_length, s)
    theta = np.zeros((len(s), len(linkage.segments)))
    theta[:, linkage.index("torso")] = shape.lean
    theta[:, linkage.index("thigh_stance")] = stance
    theta[:, linkage.index("shank_stance")] = stance + shape.knee_stance * bump
    theta[:, linkage.index("thigh_swing")] = swing - 0.5 * shape.knee_swing * bump
    theta[:, linkage.index("shank_swing")] = swing + 0.5 * shape.knee_swing * bump
    return theta
