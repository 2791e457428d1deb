"""Hermite-Simpson collocation in separated form (Kelly 2017, the paper's integrator).

States are cubic and their derivatives quadratic over each interval; knot ``2i+1`` is the
midpoint of interval ``i``, which spans ``h = 2 dt``. The functions work on numbers and on
CasADi expressions alike.
"""

from __future__ import annotations

from typing import Any

import numpy as np


def defects(y0: Any, yc: Any, y1: Any, f0: Any, fc: Any, f1: Any, h: Any) -> tuple[Any, Any]:
    """Simpson quadrature and Hermite midpoint defects of one interval (both zero when met).

    Args:
        y0, yc, y1: state at the interval start, midpoint and end.
        f0, fc, f1: state derivative at the same three points.
        h: interval duration.
    """
    simpson = y1 - y0 - (f0 + 4.0 * fc + f1) * h / 6.0
    hermite = yc - (y0 + y1) / 2.0 - (f0 - f1) * h / 8.0
    return simpson, hermite


def interpolate(times: np.ndarray, y: np.ndarray, f: np.ndarray, t: float) -> tuple[np.ndarray, np.ndarray]:
    """State and derivative at time ``t`` as the collocation assumes them.

    Args:
        times: (T,) knot times, T odd.
        y: (T, n) states at the knots.
        f: (T, n) state derivatives at the knots.
        t: query time, clipped to the trajectory.

    Returns:
        The cubic state and its (quadratic) derivative at ``t``.
    """
    n_int = (len(times) - 1) // 2
    h = times[2] - times[0]
    i = int(np.clip((t - times[0]) // h, 0, n_int - 1))
    k = 2 * i
    s = float(np.clip((t - times[k]) / h, 0.0, 1.0))
    f0, fc, f1 = f[k], f[k + 1], f[k + 2]
    # Quadratic derivative through (0, f0), (1/2, fc), (1, f1).
    deriv = f0 * (1 - 3 * s + 2 * s**2) + fc * (4 * s - 4 * s**2) + f1 * (-s + 2 * s**2)
    state = y[k] + h * (
        f0 * (s - 1.5 * s**2 + 2 / 3 * s**3) + fc * (2 * s**2 - 4 / 3 * s**3) + f1 * (-0.5 * s**2 + 2 / 3 * s**3)
    )
    return state, deriv


def quadratic(times: np.ndarray, u: np.ndarray, t: float) -> np.ndarray:
    """Control (e.g. torque) at time ``t``: the quadratic through an interval's three knots.

    Hermite-Simpson evaluates the dynamics at each interval's start, midpoint and end, so
    it treats controls as quadratic in between (Kelly 2017, section 4).

    Args:
        times: (T,) knot times, T odd.
        u: (T, m) control values at the knots.
        t: query time, clipped to the trajectory.
    """
    n_int = (len(times) - 1) // 2
    h = times[2] - times[0]
    i = int(np.clip((t - times[0]) // h, 0, n_int - 1))
    k = 2 * i
    s = float(np.clip((t - times[k]) / h, 0.0, 1.0))
    return u[k] * (1 - 3 * s + 2 * s**2) + u[k + 1] * (4 * s - 4 * s**2) + u[k + 2] * (-s + 2 * s**2)
