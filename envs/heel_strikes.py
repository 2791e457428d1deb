"""Which leg stands, and heel strikes: the gait events the environment reports in ``info``.

A demonstration is one step with its legs named by role (stance, swing); to replay it the
roles must swap at every heel strike. The environment therefore keeps a stance leg and
counts heel strikes, from the feet's floor contacts at the end of each environment step:

- the swing foot must have been off the floor at the end of some step since the last
  heel strike (it lifted off), and
- it touches the floor again **ahead** of the stance foot (forward walking).

Then the roles swap. The second rule keeps a trailing foot that scuffs the floor just
after lift-off from counting; it needs no knowledge of the step's length or duration.
"""

from __future__ import annotations

from dataclasses import dataclass

from envs.coordinates import check_stance, other_leg


@dataclass
class StanceTracker:
    """Stance leg, whether the swing foot has lifted off, and heel strikes since the reset.

    Attributes:
        stance_leg: the physical leg ("a" or "b") in the stance role.
        swing_lifted: whether the swing foot has been off the floor since the last strike.
        heel_strikes: heel strikes since the reset.
    """

    stance_leg: str = "a"
    swing_lifted: bool = False
    heel_strikes: int = 0

    def __post_init__(self) -> None:
        check_stance(self.stance_leg)

    def update(self, contact: dict[str, bool], foot_x: dict[str, float]) -> bool:
        """Account for one environment step's end state; True if it ended with a heel strike.

        Args:
            contact: leg -> whether its foot touches the floor.
            foot_x: leg -> the foot's forward position.
        """
        swing = other_leg(self.stance_leg)
        if not contact[swing]:
            self.swing_lifted = True
            return False
        if self.swing_lifted and foot_x[swing] > foot_x[self.stance_leg]:
            self.stance_leg, self.swing_lifted = swing, False
            self.heel_strikes += 1
            return True
        return False
