"""Tracking terms: the ``strength * D(x, target)`` that projections and proximal solves add.

``D`` is the mean squared difference to a target step over every measured position,
velocity and torque signal, each divided by its span in a reference step, so that every
signal counts alike whatever its unit. Signals the target does not have (NaN, e.g. torques
that were not measured) are left out. The step problem takes the target as its ``ref``
parameter and the per-entry weights as its ``track`` parameter.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Protocol

import numpy as np


class Signals(Protocol):
    """Anything with knot-by-knot positions, velocities and torques (a trajectory, an observation)."""

    def signals(self, n_actuators: int | None = None) -> np.ndarray: ...


def signal_spans(step: Signals, n_actuators: int | None = None) -> np.ndarray:
    """(n,) span (max - min) of every signal of ``step``, floored to stay positive (1 where
    the signal is missing)."""
    sig = step.signals(n_actuators)
    measured = np.isfinite(sig).all(axis=0)
    span = np.ones(sig.shape[1])
    if measured.any():
        seen = sig[:, measured]
        raw = seen.max(axis=0) - seen.min(axis=0)
        span[measured] = np.maximum(raw, 1e-3 * max(float(raw.max()), 1e-12))
    return span


@dataclass(frozen=True, eq=False)
class Tracking:
    """A tracking term ``sum(weight * (signals - ref)^2)`` over a step's (T, n) signals.

    Attributes:
        ref: (T, n) the target's signals (0 where not measured).
        weight: (T, n) each entry's weight (0 where not measured).
    """

    ref: np.ndarray
    weight: np.ndarray


def tracking_terms(target: Signals, strength: float, spans: np.ndarray) -> Tracking:
    """The tracking term ``strength * D(x, target)`` (missing signals weigh 0)."""
    ref = target.signals(_actuators(spans, target))
    measured = np.isfinite(ref)
    weights = np.where(measured, strength / (spans**2 * max(int(measured.sum()), 1)), 0.0)
    return Tracking(np.where(measured, ref, 0.0), weights)


def tracking_error(step: Signals, target: Signals, spans: np.ndarray) -> float:
    """``D(step, target)``: the mean squared span-normalised difference of the measured signals."""
    n = _actuators(spans, target)
    diff = (step.signals(n) - target.signals(n)) / spans
    return float(np.nanmean(diff**2))


def _actuators(spans: np.ndarray, target: Signals) -> int | None:
    """How many torque columns a signal vector of ``spans``'s length has past q and v."""
    q = getattr(target, "q", None)
    return None if q is None else spans.size - 2 * q[0].size
