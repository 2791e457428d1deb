"""How close a step is to an observed one: the paper's trajectory error.

One definition, one name: ``trajectory_error`` is the paper's (section III, Figure 6:
"the sum of the squared difference of each segment angle and angular velocity ... from the
observed optimal"). The span-normalised distance that algorithms and proximal solves use is
:func:`ioc_bench.trajopt.tracking.tracking_error`.
"""

from __future__ import annotations

from ioc_bench.trajectory import Observation


def trajectory_error(step: Observation, observed: Observation) -> float:
    """Sum over knots and segments of squared segment-angle and angular-velocity differences."""
    if step.n_knots != observed.n_knots:
        raise ValueError(f"cannot compare {step.n_knots} knots with {observed.n_knots}")
    d_angle = step.q[:, :, 2] - observed.q[:, :, 2]
    d_rate = step.v[:, :, 2] - observed.v[:, :, 2]
    return float((d_angle**2).sum() + (d_rate**2).sum())
