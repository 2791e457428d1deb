"""The walking task: what the step must achieve (``docs/spec.md``, "The task")."""

from __future__ import annotations

import numbers
import sys
from dataclasses import dataclass

import numpy as np

from ioc_bench.validation import shown

#: Nominal average forward speed (about 0.8 m/s for a 0.9 m leg).
NOMINAL_SPEED = 0.27
#: The "fast" gait of the ideal-fast condition (about 1.0 m/s).
FAST_SPEED = 0.34


def _positive(name: str, value: object) -> float | int:
    """``value`` if it is a positive finite real number, else ``ValueError`` naming ``name``.

    Python ints and floats are kept as they are; other reals (NumPy scalars, fractions)
    become the ``float`` of their shortest decimal, so ``np.float32(0.27)`` is 0.27 and not
    0.27000001. Integers beyond any float (``10**400``) are refused, not overflowed.
    """
    real = isinstance(value, numbers.Real) and not isinstance(value, (bool, np.bool_))
    if real and type(value) not in (int, float):
        try:
            value = float(str(value)) if isinstance(value, np.floating) else float(value)
        except (OverflowError, ValueError):
            real = False
    if not real or not 0 < value <= sys.float_info.max:
        raise ValueError(f"{name} must be a positive finite number, got {shown(value)}")
    return value


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
        object.__setattr__(self, "speed", _positive("speed", self.speed))
        if self.step_length is not None:
            object.__setattr__(self, "step_length", _positive("step_length", self.step_length))

    def to_dict(self) -> dict[str, float | None]:
        return {"speed": self.speed, "step_length": self.step_length}
