"""Hermite-Simpson transcription: knots, their spacing and the collocation defects.

The paper's integrator (Kelly 2017): states are cubic and their derivatives quadratic over
each interval. Knots are uniformly spaced and include the interval midpoints (knot
``2i + 1`` is the midpoint of interval ``i``), so ``M`` intervals give ``2M + 1`` knots.
This class knows nothing of walking: a problem hands it the states to collocate and their
time derivatives, as rockit separates an ``Ocp`` from its sampling method.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from ioc_bench.trajopt import collocation
from ioc_bench.trajopt.layout import Constraints, Layout


class HermiteSimpson:
    """``n_intervals`` Hermite-Simpson intervals with a free uniform knot spacing.

    The spacing is one decision variable per knot, chained equal: a single shared ``dt``
    would make one dense column in the constraint Jacobian and one dense row in the
    Hessian, which the sparse LDL^T factorization turns into fill.
    """

    def __init__(self, n_intervals: int):
        if n_intervals < 2:
            raise ValueError(f"need at least 2 collocation intervals, got {n_intervals}")
        self.n_intervals = n_intervals
        self.n_knots = 2 * n_intervals + 1

    def add_variables(self, layout: Layout) -> None:
        """Declare the knot spacing (block ``dt``, one copy per knot)."""
        layout.add("dt", (self.n_knots,))

    def add_constraints(self, g: Constraints, dt: np.ndarray, states: np.ndarray, rates: np.ndarray) -> None:
        """Chain the spacing copies equal and collocate ``states`` (T, n) with time derivatives
        ``rates`` (T, n): groups ``uniform_dt`` and ``collocation``."""
        g.add("uniform_dt", dt[1:] - dt[:-1])
        for i in range(self.n_intervals):
            k = 2 * i
            h = _object_scalar(2 * dt[k])
            simpson, hermite = collocation.defects(*states[k : k + 3], *rates[k : k + 3], h)
            g.add("collocation", list(simpson.ravel()) + list(hermite.ravel()))

    def duration(self, dt: np.ndarray) -> Any:
        """The trajectory's duration, from the last knot's spacing copy."""
        return (self.n_knots - 1) * dt[-1]


def _object_scalar(value: Any) -> np.ndarray:
    """Wrap a CasADi scalar so numpy broadcasts it elementwise over object arrays."""
    out = np.empty((), dtype=object)
    out[()] = value
    return out
