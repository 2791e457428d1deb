"""Scores of an IOC result (``docs/spec.md``, "Metrics"); the trajectory error is ``ioc_bench.metrics``."""

from __future__ import annotations

import numpy as np


def unit(weights: np.ndarray) -> np.ndarray:
    w = np.asarray(weights, dtype=float)
    return w / np.linalg.norm(w)


def weight_error(estimated: np.ndarray, true: np.ndarray) -> float:
    """Mean absolute difference of the unit-norm weight vectors over the features used."""
    return float(np.mean(np.abs(unit(estimated) - unit(true))))
