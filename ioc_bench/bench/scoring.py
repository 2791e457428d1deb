"""Scores of an IOC result (SPEC section 5)."""

from __future__ import annotations

import numpy as np

from ioc_bench.trajectory import Trajectory


def unit(weights: np.ndarray) -> np.ndarray:
    w = np.asarray(weights, dtype=float)
    return w / np.linalg.norm(w)


def weight_error(estimated: np.ndarray, true: np.ndarray) -> float:
    """Mean absolute difference of the unit-norm weight vectors over the features used."""
    return float(np.mean(np.abs(unit(estimated) - unit(true))))


def trajectory_error(trajectory: Trajectory, observed: Trajectory) -> float:
    """Sum over knots and segments of the squared differences of segment angle and
    angular velocity between a step and the observed one."""
    if trajectory.n_knots != observed.n_knots:
        raise ValueError(f"cannot compare {trajectory.n_knots} knots with {observed.n_knots}")
    d_angle = trajectory.q[:, :, 2] - observed.q[:, :, 2]
    d_rate = trajectory.v[:, :, 2] - observed.v[:, :, 2]
    return float(np.sum(d_angle**2) + np.sum(d_rate**2))
