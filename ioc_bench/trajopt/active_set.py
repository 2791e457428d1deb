"""Which constraints and bounds hold with equality at a point: one test for every user.

A constraint ``lower <= value <= upper`` is active at its lower side when
``value - lower <= tol * (1 + |lower|)`` (and likewise at its upper side). The forward
problem's sensitivity, its report of active bounds, the inverse-KKT fit and the
single-level IOC all ask this one function.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


def active_sides(values: np.ndarray, lower: np.ndarray, upper: np.ndarray, tol: float) -> tuple[np.ndarray, np.ndarray]:
    """Masks of the entries at their lower and at their upper bound (lower side first when
    both hold, as for an equality)."""
    with np.errstate(invalid="ignore"):
        at_lower = np.isfinite(lower) & (values - lower <= tol * (1 + np.abs(lower)))
        at_upper = np.isfinite(upper) & (upper - values <= tol * (1 + np.abs(upper))) & ~at_lower
    return at_lower, at_upper


@dataclass(frozen=True)
class ActiveSet:
    """The active set at a point ``x`` of ``lbg <= g(x) <= ubg, lbx <= x <= ubx``.

    Attributes:
        equality: (n_g,) constraints with ``lbg == ubg`` (always active).
        g_lower: (n_g,) inequality constraints at their lower bound.
        g_upper: (n_g,) inequality constraints at their upper bound.
        x_lower: (n_x,) variables at their lower bound (fixed variables included).
        x_upper: (n_x,) variables at their upper bound.
    """

    equality: np.ndarray
    g_lower: np.ndarray
    g_upper: np.ndarray
    x_lower: np.ndarray
    x_upper: np.ndarray

    @property
    def constraints(self) -> np.ndarray:
        """(n_g,) equality constraints and active inequalities."""
        return self.equality | self.g_lower | self.g_upper

    @property
    def bounds(self) -> np.ndarray:
        """(n_x,) variables at a bound."""
        return self.x_lower | self.x_upper

    @classmethod
    def at(
        cls, x: np.ndarray, g: np.ndarray, bounds: tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray], tol: float
    ) -> ActiveSet:
        """The active set at ``x`` with constraint values ``g`` and ``bounds`` = (lbx, ubx, lbg, ubg)."""
        lbx, ubx, lbg, ubg = bounds
        equality = lbg == ubg
        g_lower, g_upper = active_sides(g, lbg, ubg, tol)
        x_lower, x_upper = active_sides(x, lbx, ubx, tol)
        return cls(equality, g_lower & ~equality, g_upper & ~equality, x_lower, x_upper)
