"""The region of weights a cutting-plane method's cuts leave: how sure its answer is.

Each cut (a suboptimal sample ``x_i``) keeps the weights under which the sample costs at
least ``(1 - t)`` times the reference, ``d_i . w >= 0`` with ``d_i = phi(x_i) - (1 - t) phi(ref)``.
Every weight vector in that cone explains the reference as well as the cuts can tell, so
the cone is the method's region for the weights. Its per-weight extent over unit-norm
weights is found from points of the cone's section by the simplex ``sum w = 1``: its
vertices (linear programs in the coordinate directions and random ones) and a hit-and-run
walk through it (``scipy.optimize.linprog``; seeded: the same cuts give the same region).
When the cuts leave no weights (the method stopped ``infeasible``), the cone relaxed just
enough to be non-empty is used, and the region says so.
"""

from __future__ import annotations

import numpy as np
from scipy.optimize import linprog

from ioc_bench.ioc.algorithm import WeightRegion

#: Random linear-program directions and hit-and-run points per region.
DIRECTIONS = 40
WALK = 2000


def cut_region(diffs: np.ndarray | None, n_features: int, lower: float = 0.0, seed: int = 0) -> WeightRegion | None:
    """The per-weight extent of ``{w >= lower : diffs @ w >= -relax |diffs|}`` over unit-norm
    weights (``relax`` 0 unless no weights satisfy every cut); None if it cannot be found."""
    unit = _unit_rows(np.zeros((0, n_features)) if diffs is None else np.atleast_2d(np.asarray(diffs, dtype=float)))
    relax = max(0.0, -_margin(unit, lower)) * 1.5
    rng = np.random.default_rng(seed)
    points = _vertices(unit, relax, lower, rng)
    if not points:
        return None
    points += _walk(unit, relax, lower, np.mean(points, axis=0), rng)
    u = np.array([p / np.linalg.norm(p) for p in points])
    method = "weights every cut keeps (cutting-plane cone)"
    if relax > 0:
        method += f", relaxed by {relax:.2g} (no weights satisfied every cut)"
    return WeightRegion(tuple(u.min(axis=0)), tuple(u.max(axis=0)), 0.95, None, method)


def _unit_rows(diffs: np.ndarray) -> np.ndarray:
    norms = np.linalg.norm(diffs, axis=1)
    return diffs[norms > 0] / norms[norms > 0, None]


def _bounds(unit: np.ndarray, relax: float, lower: float) -> dict:
    n = unit.shape[1]
    return {
        "A_ub": -unit if unit.size else None,
        "b_ub": np.full(unit.shape[0], relax) if unit.size else None,
        "A_eq": np.ones((1, n)),
        "b_eq": [1.0],
        "bounds": [(lower / np.sqrt(n), None)] * n,
    }


def _margin(unit: np.ndarray, lower: float) -> float:
    """max_w min_i unit_i . w over the simplex (negative: no weights satisfy every cut)."""
    if not unit.size:
        return 1.0
    n = unit.shape[1]
    c = np.zeros(n + 1)
    c[-1] = -1.0
    res = linprog(
        c,
        A_ub=np.hstack([-unit, np.ones((unit.shape[0], 1))]),
        b_ub=np.zeros(unit.shape[0]),
        A_eq=np.append(np.ones(n), 0.0)[None, :],
        b_eq=[1.0],
        bounds=[(lower / np.sqrt(n), None)] * n + [(None, None)],
        method="highs",
    )
    return float(-res.fun) if res.success else 0.0


def _vertices(unit: np.ndarray, relax: float, lower: float, rng: np.random.Generator) -> list[np.ndarray]:
    n = unit.shape[1]
    directions = [s * e for e in np.eye(n) for s in (1.0, -1.0)] + list(rng.normal(size=(DIRECTIONS, n)))
    out = []
    for d in directions:
        res = linprog(-d, method="highs", **_bounds(unit, relax, lower))
        if res.success:
            out.append(np.maximum(res.x, 0.0))
    return out


def _walk(
    unit: np.ndarray, relax: float, lower: float, start: np.ndarray, rng: np.random.Generator
) -> list[np.ndarray]:
    """Hit-and-run points of the section by the simplex, from an interior ``start``."""
    n = unit.shape[1]
    floor = lower / np.sqrt(n)
    a = np.vstack([unit, np.eye(n)]) if unit.size else np.eye(n)
    b = np.concatenate([np.full(unit.shape[0], -relax), np.full(n, floor)]) if unit.size else np.full(n, floor)
    x, out = start.copy(), []
    for _ in range(WALK):
        d = rng.normal(size=n)
        d -= d.mean()  # stay on sum w = 1
        rate, slack = a @ d, a @ x - b
        with np.errstate(divide="ignore", invalid="ignore"):
            steps = -slack / rate
        hi = np.min(steps[rate < 0], initial=np.inf)
        lo = np.max(steps[rate > 0], initial=-np.inf)
        if not (np.isfinite(lo) and np.isfinite(hi)) or hi <= lo:
            continue
        x = x + rng.uniform(lo, hi) * d
        out.append(np.maximum(x, 0.0))
    return out
