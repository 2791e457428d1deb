"""Model-free predictions of a person's gait at another speed, for a cost model to beat.

A biomechanist without a cost model would predict a person's step at a new speed by:
copying the step at the training speed (no change); adding the population's mean change
between the same two speeds; interpolating linearly in speed between two training speeds;
or, for the step length, a population power law of step length on speed. These are
computed here from the people's steps alone, without any solve, and scored with
:func:`log_error` (step length, cadence) and :func:`change_r2` (the change of the angles).
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:
    from ioc_bench.human.step import HumanStep


@dataclass(frozen=True, eq=False)
class Interpolated:
    """A step predicted by linear interpolation in belt speed.

    Attributes:
        angles: (T, 4) segment angles, rad.
        step_length: step length, leg lengths.
    """

    angles: np.ndarray
    step_length: float


def population_change(others: Sequence[tuple[HumanStep, HumanStep]]) -> np.ndarray | None:
    """Mean (T, 4) change of the angles from ``there`` to ``here`` over other subjects.

    Each pair is (step at the training speed, step at the predicted speed) of one other
    subject. The population prediction is ``train.angles + change``: people share much of
    how their gait changes with speed. None when there are no pairs.
    """
    if not others:
        return None
    return np.mean([here.angles - there.angles for there, here in others], axis=0)


def interpolate(training: Sequence[HumanStep], target_speed: float) -> Interpolated | None:
    """Angles and step length linear in belt speed between the training steps around the target.

    Uses the nearest training step strictly below ``target_speed`` and the nearest strictly
    above (by ``task.speed``). None when the target is not strictly bracketed: outside the
    training speeds (no extrapolation) or equal to one of them (a speed trained on is not
    predicted).
    """
    speeds = [step.task.speed for step in training]
    if target_speed in speeds:
        return None
    below = [s for s in training if s.task.speed < target_speed]
    above = [s for s in training if s.task.speed > target_speed]
    if not below or not above:
        return None
    lo = max(below, key=lambda s: s.task.speed)
    hi = min(above, key=lambda s: s.task.speed)
    w = (target_speed - lo.task.speed) / (hi.task.speed - lo.task.speed)
    angles = (1.0 - w) * np.asarray(lo.angles) + w * np.asarray(hi.angles)
    step_length = (1.0 - w) * lo.task.step_length + w * hi.task.step_length
    return Interpolated(angles=angles, step_length=float(step_length))


def power_law_exponent(steps: Sequence[HumanStep]) -> float:
    """Exponent b of ``step_length ~ speed**b``, least squares in log-log over ``steps``.

    Walker units (speed / sqrt(g L), step length / L), pooled over whichever subjects the
    steps come from: the population's trend of step length on speed.

    Raises:
        ValueError: fewer than two distinct speeds, or a speed or step length not positive.
    """
    speeds = np.array([s.task.speed for s in steps], dtype=float)
    lengths = np.array([s.task.step_length for s in steps], dtype=float)
    if len(set(speeds.tolist())) < 2:
        raise ValueError(f"a power law needs at least 2 distinct speeds, got {len(set(speeds.tolist()))}")
    if not (np.all(speeds > 0) and np.all(lengths > 0)):
        raise ValueError("a power law needs positive speeds and step lengths")
    slope, _ = np.polyfit(np.log(speeds), np.log(lengths), 1)
    return float(slope)


def power_law_step_length(train: HumanStep, target_speed: float, exponent: float) -> float:
    """Step length at ``target_speed`` scaled from the training step by the power law."""
    return float(train.task.step_length * (target_speed / train.task.speed) ** exponent)


def log_error(predicted: float, measured: float) -> float:
    """``|log(predicted / measured)|``: a symmetric relative error of a positive quantity.

    NaN when either is not finite or not positive (a failed prediction).
    """
    if not all(math.isfinite(x) and x > 0 for x in (predicted, measured)):
        return float("nan")
    return abs(math.log(predicted / measured))


def _sums(predicted_change: np.ndarray | None, person_change: np.ndarray) -> tuple[float, float] | None:
    """(sum of squared errors, sum of the person's squared change); None for a failed prediction."""
    if predicted_change is None:
        return None
    pred = np.asarray(predicted_change, dtype=float)
    if not np.all(np.isfinite(pred)):
        return None
    person = np.asarray(person_change, dtype=float)
    return float(np.sum((pred - person) ** 2)), float(np.sum(person**2))


def _r2(error: float, total: float) -> float:
    return 1.0 - error / total if total > 0 else float("nan")


def change_r2(predicted_change: np.ndarray | None, person_change: np.ndarray) -> float:
    """Share of the person's (T, 4) change of angles that a prediction explains.

    ``1 - sum((pred - person)**2) / sum(person**2)``: 1 for the exact change, exactly 0 for
    the copy (a predicted change of zeros), negative for a change worse than none. NaN when
    the prediction is None or not finite, or the person's change is all zero.
    """
    sums = _sums(predicted_change, person_change)
    return float("nan") if sums is None else _r2(*sums)


def pooled_change_r2(pairs: Iterable[tuple[np.ndarray | None, np.ndarray]]) -> float:
    """:func:`change_r2` pooled over (predicted change, person's change) pairs.

    ``1 - sum of squared errors / sum of the person's squared changes`` over all pairs, so
    larger changes weigh more; pairs whose prediction is None or not finite are skipped.
    The copy gives exactly 0. NaN when no pair is left.
    """
    sums = [s for s in (_sums(pred, person) for pred, person in pairs) if s is not None]
    if not sums:
        return float("nan")
    return _r2(sum(e for e, _ in sums), sum(t for _, t in sums))


def cadence(step_length: float, speed: float) -> float:
    """Steps per walker time unit, ``speed / step_length``.

    At a fixed speed, a predicted cadence's :func:`log_error` equals its step length's.
    """
    return float(speed / step_length)
