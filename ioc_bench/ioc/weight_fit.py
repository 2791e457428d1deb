"""The weight optimization at the core of the paper's IOC (``docs/spec.md``, "The baseline IOC method", step 2).

Given feature differences ``d_i = phi(x_i^-) - phi(x*)`` of suboptimal samples, find unit
weights in ``[lower, upper]`` under which every sample costs more than the observation
(``w . d_i > 0``) and which separate them well. Two objectives:

- ``"paper"``: maximise ``sum_i log(offset + w . d_i)`` on the raw differences, as printed;
- ``"center"``: maximise ``sum_i log(w . d_i / |d_i|)``, the analytic centre of the cone of
  separating weights (used by the analytic-centre cutting-plane variant).

A sample near the observation can differ from it by less than IPOPT's constraint
tolerance in raw units, so the separation constraints are imposed on unit-scaled rows
``w . d_i / |d_i| >= 0``: the same feasible set, enforced whatever the features' scale.
"""

from __future__ import annotations

from dataclasses import dataclass

import casadi as ca
import numpy as np

from ioc_bench.trajopt import ipopt

#: Tight tolerances (the separations are small); no bound relaxation (BASE): the centre
#: objective takes logs of the iterates. An iterate outside the paper objective's domain
#: (``offset + w . d <= 0``) is IPOPT's to step back from, not a warning for the user.
_OPTIONS = ipopt.options({"show_eval_warnings": False}, tol=1e-10, constr_viol_tol=1e-10, max_iter=500)


@dataclass(frozen=True)
class WeightFit:
    """Result of one weight optimization.

    Attributes:
        weights: (F,) the optimum (unit norm), or the start point if it failed.
        success: a separating weight vector was found.
        status: IPOPT's status.
        min_margin: smallest scaled separation ``min_i w . d_i / |d_i|`` (>= 0 when valid).
    """

    weights: np.ndarray
    success: bool
    status: str
    min_margin: float


def fit_weights(
    diffs: np.ndarray,
    objective: str = "paper",
    offset: float = 1.5,
    lower: float = 0.001,
    upper: float = 0.999,
    start: np.ndarray | None = None,
    relax: float = 0.0,
) -> WeightFit:
    """Solve the weight optimization for the (n, F) differences ``diffs``.

    ``relax > 0`` loosens every separation to ``w . d_i / |d_i| >= -relax`` (for samples
    no weights separate; see :func:`max_margin`).
    """
    diffs = np.atleast_2d(np.asarray(diffs, dtype=float))
    f = diffs.shape[1]
    unit = _unit_rows(diffs)
    w = ca.SX.sym("w", f)
    s = ca.SX.sym("s", unit.shape[0])  # scaled separations, kept >= 0
    if objective == "paper":
        obj = -ca.sum1(ca.log(offset + ca.mtimes(ca.DM(diffs), w)))
    elif objective == "center":
        # The cone's walls w_j >= lower are cuts too: centre among all of them.
        obj = -ca.sum1(ca.log(s)) - ca.sum1(ca.log(w - lower + 1e-12))
    else:
        raise ValueError(f"unknown weight objective {objective!r}; valid: paper, center")
    g = ca.vertcat(s - ca.mtimes(ca.DM(unit), w) - relax, ca.sumsqr(w) - 1)
    solver = ca.nlpsol("weights", "ipopt", {"x": ca.vertcat(w, s), "f": obj, "g": g}, _OPTIONS)
    w0 = _start(start, f, lower, upper)
    s0 = np.maximum(unit @ w0 + relax, 1e-3)
    sol = solver(
        x0=np.concatenate([w0, s0]),
        lbx=np.concatenate([np.full(f, lower), np.zeros(len(s0))]),
        ubx=np.concatenate([np.full(f, upper), np.full(len(s0), np.inf)]),
        lbg=np.zeros(len(s0) + 1),
        ubg=np.zeros(len(s0) + 1),
    )
    status = str(solver.stats()["return_status"])
    weights = np.asarray(sol["x"], dtype=float).ravel()[:f]
    margin = float(np.min(unit @ weights, initial=np.inf))
    ok = ipopt.converged(status) and margin >= -relax - 1e-8
    if not ok:
        weights = w0
    return WeightFit(weights=weights / np.linalg.norm(weights), success=ok, status=status, min_margin=margin)


def max_margin(diffs: np.ndarray, lower: float = 0.0, upper: float = 1.0, start: np.ndarray | None = None) -> float:
    """The largest achievable smallest scaled separation ``max_w min_i w . d_i / |d_i|``.

    Negative when no weights separate every sample; then ``-max_margin`` is how far the
    separations must be relaxed for any weights to exist.
    """
    return _max_margin(diffs, lower, upper, start)[1]


def best_separating(diffs: np.ndarray, lower: float = 0.0, upper: float = 1.0) -> np.ndarray:
    """The unit weights in ``[lower, upper]`` that achieve :func:`max_margin`: where no weights
    separate every sample, those under which the worst-separated sample is least cheaper."""
    return _max_margin(diffs, lower, upper, None)[0]


def _max_margin(diffs, lower, upper, start) -> tuple[np.ndarray, float]:
    unit = _unit_rows(np.atleast_2d(np.asarray(diffs, dtype=float)))
    f, n = unit.shape[1], unit.shape[0]
    w, t = ca.SX.sym("w", f), ca.SX.sym("t")
    g = ca.vertcat(ca.mtimes(ca.DM(unit), w) - t, ca.sumsqr(w) - 1)
    solver = ca.nlpsol("margin", "ipopt", {"x": ca.vertcat(w, t), "f": -t, "g": g}, _OPTIONS)
    w0 = _start(start, f, lower, upper)
    sol = solver(
        x0=np.append(w0, float(np.min(unit @ w0, initial=0.0))),
        lbx=np.append(np.full(f, lower), -np.inf),
        ubx=np.append(np.full(f, upper), np.inf),
        lbg=np.zeros(n + 1),
        ubg=np.append(np.full(n, np.inf), 0.0),
    )
    x = np.asarray(sol["x"], dtype=float).ravel()
    return x[:-1] / np.linalg.norm(x[:-1]), float(x[-1])


def _unit_rows(diffs: np.ndarray) -> np.ndarray:
    norms = np.linalg.norm(diffs, axis=1)
    keep = norms > 0
    return diffs[keep] / norms[keep, None]


def _start(start: np.ndarray | None, f: int, lower: float, upper: float) -> np.ndarray:
    w0 = np.full(f, 1.0 / np.sqrt(f)) if start is None else np.clip(np.asarray(start, dtype=float), lower, upper)
    return w0 / np.linalg.norm(w0)
