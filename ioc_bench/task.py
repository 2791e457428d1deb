"""The walking task: what the step must achieve (SPEC section 2)."""

from __future__ import annotations

import math
from dataclasses import dataclass

#: Nominal average forward speed (about 0.8 m/s for a 0.9 m leg).
NOMINAL_SPEED = 0.27
#: The "fast" gait of the ideal-fast condition (about 1.0 m/s).
FAST_SPEED = 0.34


@dataclass(frozen=True)
class Task:
    """A periodic step at average forward ``speed`` (leg lengths per time unit).

    Step length and duration are free; only their ratio is fixed.
    """

    speed: float = NOMINAL_SPEED

    def __post_init__(self) -> None:
        number = isinstance(self.speed, (int, float)) and not isinstance(self.speed, bool)
        if not (number and math.isfinite(self.speed) and self.speed > 0):
            raise ValueError(f"speed must be a positive finite number, got {self.speed!r}")
