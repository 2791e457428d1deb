"""Does the model fit the observation? A residual test, and the region it conditions.

A fit's tracking residual (the span-normalised differences between the model's optimum for
the fitted weights and the observation, ``docs/differentiable.md``) is noise when the model
can produce the observation, and more than noise when it cannot (a wrong mass, a wrong
speed). The noise level is estimated from the observation itself
(:func:`~ioc_bench.ioc.smoothing.noise_level`: fourth differences, median absolute
deviation), so the test needs nothing but the observation and the fit::

    statistic = sum_k m_k D_k / sigma_k^2 / (sum_k m_k - (F - 1))

over the trials ``k`` (``m_k`` measured values, ``D_k`` the tracking error, ``sigma_k`` the
estimated noise, at least :data:`PRECISION`). Under the model with independent noise of
that level the statistic is a chi-square over its degrees of freedom, about 1; the model is
rejected above :data:`THRESHOLD` (``docs/ioc.md`` has the measured false-alarm rate and
power). A region made from the residual's spread (:func:`gauss_newton_region`) describes
noise around the model; when the model is rejected it is conditional on a model the data
reject.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from ioc_bench.ioc.algorithm import ModelFit, WeightRegion
from ioc_bench.ioc.inverse_kkt import interval
from ioc_bench.ioc.oracle import OracleSolution
from ioc_bench.ioc.smoothing import NOISE_FLOOR

#: The smallest noise level the test assumes (a fraction of span): the level below which the
#: reference calls an observation exact (:data:`~ioc_bench.ioc.smoothing.NOISE_FLOOR`). Below
#: it the estimate reads the signal's own curvature (2e-5 to 8e-5 on the benchmark's exact
#: demonstrations), and fits that are exact to the weights' resolution leave more: with the
#: solves' precision (1e-6) as the floor, single-level fits of exact observations with weight
#: errors of 1e-4 were rejected (``docs/ioc.md``).
PRECISION = NOISE_FLOOR
#: The statistic above which the data reject the model (see ``docs/ioc.md`` for how it was
#: chosen: the noise estimate's own error on the benchmark's noisy observations, far above a
#: chi-square quantile of ~1400 values).
THRESHOLD = 2.0
#: What the test is, for the record.
METHOD = "tracking residual over the observation's own noise estimate (fourth differences, MAD)"


def _count(trial) -> int:
    _, weight = trial.forward.tracking_quadratic()
    return int(np.count_nonzero(weight))


def residual_test(trials: Sequence, steps: Sequence, n_features: int) -> ModelFit:
    """The misfit test of one step per trial (oracle solutions or trajectories) against each
    trial's observation; see the module docstring."""
    errors, counts, levels = [], [], []
    for trial, step in zip(trials, steps, strict=True):
        trajectory = step.trajectory if isinstance(step, OracleSolution) else step
        errors.append(float(trial.tracking_error(trajectory)))
        counts.append(_count(trial))
        levels.append(max(float(trial.noise_level), PRECISION))
    m, d, s = np.array(counts, dtype=float), np.array(errors), np.array(levels)
    dof = max(float(m.sum()) - (n_features - 1), 1.0)
    statistic = float(np.sum(m * d / s**2) / dof)
    return ModelFit(
        rejected=bool(statistic > THRESHOLD),
        statistic=statistic,
        threshold=THRESHOLD,
        noise_level=float(np.sqrt(np.sum(m * s**2) / m.sum())),
        tracking_error=float(np.mean(d)),
        method=METHOD,
    )


def tracking_residuals(trials: Sequence, solutions: Sequence[OracleSolution]) -> tuple[np.ndarray, np.ndarray]:
    """The stacked tracking residuals ``r`` of each trial's forward optimum (``r . r`` the sum
    of the trials' tracking errors) and their Jacobian by the weights (``(m, F)``, from each
    optimum's KKT sensitivity)."""
    parts, blocks = [], []
    for trial, sol in zip(trials, solutions, strict=True):
        view = trial.forward
        ref, weight = view.tracking_quadratic()
        rows = np.flatnonzero(weight > 0)
        sqrt_w = np.sqrt(weight[rows])
        parts.append(sqrt_w * (view.vector(sol.trajectory)[rows] - ref[rows]))
        blocks.append(sqrt_w[:, None] * view.sensitivity(sol)[rows])
    return np.concatenate(parts), np.vstack(blocks)


def gauss_newton_region(residual: np.ndarray, jacobian: np.ndarray, w: np.ndarray, method: str) -> WeightRegion:
    """The 95 % region of unit-norm weights ``w`` from the Gauss-Newton covariance
    ``s^2 (J^T J)^-1`` of a least-squares fit in the unit sphere's tangent space (``s^2`` the
    residual variance), mapped to each weight (``w_i +- 1.96 sd_i``, at least the weights'
    resolution, clipped to [0, 1])."""
    basis = np.linalg.svd(np.eye(w.size) - np.outer(w, w))[0][:, : w.size - 1]
    jt = jacobian @ basis
    dof = max(residual.size - (w.size - 1), 1)
    variance = float(residual @ residual) / dof
    cov = basis @ (variance * np.linalg.pinv(jt.T @ jt)) @ basis.T
    cov = (cov + cov.T) / 2
    lower, upper = interval(w, np.sqrt(np.maximum(np.diag(cov), 0.0)))
    return WeightRegion(tuple(lower), tuple(upper), 0.95, tuple(map(tuple, cov)), method)
