"""The walking task: what the step must achieve (SPEC section 2)."""

from __future__ import annotations

import math
from dataclasses import dataclass

#: Nominal average forward speed (about 0.8 m/s for a 0.9 m leg).
NOMINAL_SPEED = 0.27
#: The "fast" gait of the ideal-fast condition (about 1.0 m/s).
FAST_SPEED = 0.34


def _positive(name: str, value: object) -> None:
    if isinstance(value, bool) or not (isinstance(value, (int, float)) and math.isfinite(value) and value > 0):
        raise ValueError(f"{name} must be a positive finite number, got {value!r}")


@dataclass(frozen=True)
class Task:
    """A periodic step at average forward ``speed`` (leg lengths per time unit).

    Attributes:
        speed: average forward speed.
        step_length: if set, the step must have this length (leg lengths); by default the
            step length and duration are free and only their ratio (the speed) is fixed.
    """

    speed: float = NOMINAL_SPEED
    step_length: float | None = None

    def __post_init__(self) -> None:
        _positive("speed", self.speed)
        if self.step_length is not None:
            _positive("step_length", self.step_length)

    def to_dict(self) -> dict[str, float | None]:
        return {"speed": self.speed, "step_length": self.step_length}
