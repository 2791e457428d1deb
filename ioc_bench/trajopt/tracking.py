"""Tracking terms: the ``strength * D(x, target)`` that projections and proximal solves add.

``D`` is the mean squared difference to a target step over every measured position,
velocity and torque signal, each divided by its span in a reference step, so that every
signal counts alike whatever its unit. Signals the target does not have (NaN, e.g. torques
that were not measured) are left out. The step problem takes the target as its ``ref``
parameter and the per-entry weights as its ``track`` parameter.
"""

from __future__ import annotations

from typing import Protocol

import numpy as np


class Signals(Protocol):
    """Anything with knot-by-knot positions, velocities and torques (a trajectory, an observation)."""

    def signals(self, n_actuators: int | None = None) -> np.ndarray: ...


def signal_spans(step: Signals, n_actuators: int | None = None) -> np.ndarray:
    """(n,) span (max - min) of every signal of ``step``, floored to stay positive (1 where
    the signal is missing)."""
    sig = step.signals(n_actuators)
    with np.errstate(invalid="ignore"):
        span = np.nanmax(sig, axis=0) - np.nanmin(sig, axis=0) if np.isfinite(sig).any() else np.ones(sig.shape[1])
    span = np.where(np.isfinite(span), span, np.nan)
    floor = 1e-3 * max(float(np.nanmax(span, initial=0.0)), 1e-12)
    return np.where(np.isfinite(span), np.maximum(span, floor), 1.0)


def tracking_terms(target: Signals, strength: float, spans: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Reference and weights of ``strength * D(x, target)`` (missing signals weigh 0)."""
    ref = target.signals(_actuators(spans, target))
    measured = np.isfinite(ref)
    weights = np.where(measured, strength / (spans**2 * max(int(measured.sum()), 1)), 0.0)
    return np.where(measured, ref, 0.0), weights


def tracking_error(step: Signals, target: Signals, spans: np.ndarray) -> float:
    """``D(step, target)``: the mean squared span-normalised difference of the measured signals."""
    n = _actuators(spans, target)
    diff = (step.signals(n) - target.signals(n)) / spans
    return float(np.nanmean(diff**2))


def _actuators(spans: np.ndarray, target: Signals) -> int | None:
    """How many torque columns a signal vector of ``spans``'s length has past q and v."""
    q = getattr(target, "q", None)
    return None if q is None else spans.size - 2 * q[0].size
