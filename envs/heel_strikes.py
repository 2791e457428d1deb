"""Which leg stands, and heel strikes: the gait events the environment reports in ``info``.

A demonstration is one step with its legs named by role (stance, swing); to replay it the
roles must swap at every heel strike. The environment therefore keeps a stance leg and
counts heel strikes, from the feet's floor contacts after **every physics step** (so the
swing foot's friction, which follows the roles, switches within one physics step of the
landing whatever the ``frame_skip``). A heel strike is a *landing*:

- the swing foot must have been off the floor since the last heel strike (it lifted off),
- it touches the floor again, and
- it is ahead of the stance foot by more than the episode's **landing distance**.

Then the roles swap. The landing distance tells a landing from a *graze*. The trajectory
optimizer lets the swing foot touch the ground at height 0 mid-swing with no force, and
its optima use that: the benchmark's steps touch the ground up to 0.54 of their step
length ahead of the stance foot (and come within 1e-3 leg lengths of it up to 0.67),
while their final descent to the landing starts beyond 0.85. A graze is no heel strike
in the optimizer's model, so it must not swap the roles here. An episode started from a
demonstration therefore counts a touchdown as the landing only beyond
:data:`LANDING_FRACTION` (3/4) of the demonstration's step length. Measured in the
closed-loop check of the eight benchmark demonstrations (10 steps each), the grazes began
up to 0.71 of the step ahead; of the 80 landings 76 began 0.93-1.08 of it ahead, three
at 0.76-0.79 (penalize-knee 0.27, once its walk had drifted), and one began as a graze
at 0.38 and slid, frictionless, into the landing zone
(docs/notes/2026-11-25-grazing-swing-feet.md). A standing start has no demonstration and
no step length: its landing distance is 0, any touchdown ahead of the stance foot is a
landing (which also keeps a trailing foot that scuffs the floor just after lift-off from
counting).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

from envs.coordinates import check_stance, other_leg
from ioc_bench.model.catalogue import get_model

if TYPE_CHECKING:
    from ioc_bench.demo import Demonstration

#: Fraction of a demonstration's step length beyond which a touchdown of the swing foot
#: ahead of the stance foot is its landing (nearer, a graze).
LANDING_FRACTION = 0.75


def step_length(demo: Demonstration) -> float:
    """How far ahead of the stance foot the demonstration's swing foot lands (leg lengths).

    Measured between the feet's points (a rolling arc's centre, right above its contact
    point), as the environment measures its feet (the sites ``foot_<leg>``).
    """
    model = get_model(demo.model)
    link = model.linkage(demo.params)
    swing = demo.trajectory.point(link, *model.roles.swing_foot)
    stance = demo.trajectory.point(link, *model.roles.stance_foot)
    return float(swing[-1, 0] - stance[-1, 0])


def landing_distance(demo: Demonstration | None) -> float:
    """The landing distance of an episode started from ``demo`` (0 for a standing start)."""
    return 0.0 if demo is None else LANDING_FRACTION * step_length(demo)


@dataclass
class StanceTracker:
    """Stance leg, whether the swing foot has lifted off, and heel strikes since the reset.

    Attributes:
        stance_leg: the physical leg ("a" or "b") in the stance role.
        swing_lifted: whether the swing foot has been off the floor since the last strike.
        heel_strikes: heel strikes since the reset.
        landing_distance: how far ahead of the stance foot a touchdown must be to count as
            the landing (leg lengths; 0: anywhere ahead).
    """

    stance_leg: str = "a"
    swing_lifted: bool = False
    heel_strikes: int = 0
    landing_distance: float = 0.0

    def __post_init__(self) -> None:
        check_stance(self.stance_leg)
        if not self.landing_distance >= 0:
            raise ValueError(f"landing_distance must be >= 0, got {self.landing_distance}")

    def update(self, contact: dict[str, bool], foot_x: dict[str, float]) -> bool:
        """Account for one physics step's end state; True if it ended with a heel strike.

        Args:
            contact: leg -> whether its foot touches the floor.
            foot_x: leg -> the foot's forward position.
        """
        swing = other_leg(self.stance_leg)
        if not contact[swing]:
            self.swing_lifted = True
            return False
        if self.swing_lifted and foot_x[swing] - foot_x[self.stance_leg] > self.landing_distance:
            self.stance_leg, self.swing_lifted = swing, False
            self.heel_strikes += 1
            return True
        return False
