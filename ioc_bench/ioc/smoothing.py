"""The feasible reference of a noisy observation: a projection that does not fit the noise.

The plain projection (the feasible step closest to the observation) fits noise: without
measured torques it explains noisy kinematics with fast-changing torques whose features are
60-35,000x the true step's, and with noisy torques it keeps their noise (phi_dtau 5x). A
step that is optimal for no weights is a poor start for every method that reads features or
optimality off it (``docs/ioc.md``).

So a noisy observation's reference is a *smoothed* projection: the tracking term plus
``mu * sum (tau_{k+1} - 2 tau_k + tau_{k-1})^2``, a torque-curvature penalty that is no cost
feature (``phi_dtau`` is the first difference). Its strength ``mu`` follows a discrepancy
rule: the noise level ``sigma`` is estimated from the observation itself
(:func:`noise_level`, from fourth differences, which remove a smooth signal), and ``mu``
is the largest of a ladder whose tracking error stays within half of the gap between the
plain projection's error ``D0`` and the noise's own, ``D <= D0 + (sigma^2 - D0) / 2``.
Morozov's principle (``D = sigma^2``: the error the true step itself has) over-smoothed in
the measurements (``docs/ioc.md``): features biased by up to 30 %, where half the gap keeps
them within about 10 %.
"""

from __future__ import annotations

import numpy as np

#: Below this estimated noise level (fraction of each signal's span) an observation is exact
#: (measured on the benchmark's demonstrations: 1e-4 and below; 1 % noise reads 0.011).
NOISE_FLOOR = 1e-3
#: Smoothing strengths tried, relative to the projection's tracking scale, weakest first.
LADDER = (1.0, 10.0, 100.0, 1000.0)
#: The share of the gap between the plain projection's tracking error and the noise level
#: that smoothing may use.
GAP_SHARE = 0.5
#: Fourth differences of independent noise of unit variance have variance 70.
_D4_VARIANCE = 70.0


def noise_level(signals: np.ndarray) -> float:
    """The noise of (T, n) signals as a fraction of each signal's span (median over signals).

    Each measured column's fourth differences remove a smooth (locally cubic) signal and
    keep the noise; their median absolute deviation estimates its standard deviation
    robustly. Columns with NaN (not measured) are left out.
    """
    measured = np.isfinite(signals).all(axis=0)
    sig = signals[:, measured]
    if sig.shape[0] < 6 or sig.shape[1] == 0:
        return 0.0
    span = np.maximum(sig.max(axis=0) - sig.min(axis=0), 1e-12)
    d4 = np.diff(sig, 4, axis=0)
    mad = np.median(np.abs(d4 - np.median(d4, axis=0)), axis=0) / 0.6745
    return float(np.median(mad / np.sqrt(_D4_VARIANCE) / span))


def discrepancy_target(plain_error: float, sigma: float) -> float:
    """The largest tracking error a smoothed projection may have (see the module docstring)."""
    return plain_error + GAP_SHARE * max(sigma**2 - plain_error, 0.0)
