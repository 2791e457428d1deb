"""The forward optimum of given weights in the observed step's basin.

A forward solve started at the feasible reference normally reaches the optimum of the
weights nearest the observation. When the observation has no torques the reference's
torques are inferred, and from there a solve can reach another local optimum of the same
weights: for the true weights of one kinematics-only case, 0.1 % costlier and 0.14 rad
away, one the data reject (``docs/ioc.md``, the noise-kinematics section). A proximal step
(the weights' cost plus ``proximal`` times the tracking error to the reference), then a
solve warm from there without the term, reaches another of the weights' optima, often the
observed step's. Neither solve is always the nearer (measured on an exact observation: the
proximal step at weight 100 wandered off to an optimum 5 % costlier and 0.17 rad away), so
both are made and the optimum with the lower tracking error is kept.
"""

from __future__ import annotations

import numpy as np

from ioc_bench.ioc.oracle import OracleSolution
from ioc_bench.ioc.problem import IOCProblem


def nearest_optimum(problem: IOCProblem, weights: np.ndarray, start: OracleSolution, proximal: float) -> OracleSolution:
    """The optimum of ``weights`` nearest the observation (lower tracking error) of a solve
    straight from ``start`` and one through a proximal step of weight ``proximal``, when the
    observation has no torques; the straight solve alone when it has, or when ``proximal``
    is 0. Three forward solves instead of one."""
    straight = problem.optimize(weights, start=start)
    if proximal <= 0 or problem.observed.tau is not None:
        return straight
    step = problem.optimize(weights, start=start, proximal=proximal)
    if not step.success:
        return straight
    released = problem.optimize(weights, start=step)
    if not released.success:
        return straight
    if straight.success and problem.tracking_error(straight.trajectory) <= problem.tracking_error(released.trajectory):
        return straight
    return released
