"""Inverse KKT: the weights under which the observed step best satisfies the optimality conditions.

After Puydupin-Jamin, Johnson & Bretl, "A convex approach to inverse optimal control and
its application to modeling human locomotion" (ICRA 2012), and Englert, Vien & Toussaint,
"Inverse KKT: Learning cost functions of manipulation tasks from demonstrations" (IJRR
2017). At the observation projected onto the IOC's model and task, ``x^``, the forward
problem's stationarity condition (``problem.forward``, IPOPT's sign convention)::

    s J_phi(x^)^T w + c grad R(x^) + J_g(x^)^T lam + lam_x = 0

is linear in the weights ``w``, the penalty's coefficient ``c`` and the multipliers. With
``x^``'s active set, equality constraints have free multipliers, active inequalities and
bounds sign-constrained ones, inactive ones none. The algorithm minimises the residual's
squared norm over ``w >= 0`` with ``sum(w) = 1``, ``c >= 0`` and the multipliers: a bounded
linear least-squares problem (``scipy.optimize.lsq_linear``). The free multipliers are
eliminated first by projecting onto the complement of the equality Jacobian's row space
(one sparse factorisation), which leaves a problem with a column per weight, per active
inequality and per active bound. The weights are normalised in units of their own
columns' norms (each feature's projected gradient), so no feature wins by being small.
One projection and no forward solve.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla
from scipy.optimize import lsq_linear

from ioc_bench.ioc.algorithm import IOCAlgorithm, IOCResult
from ioc_bench.ioc.problem import IOCProblem
from ioc_bench.ioc.registry import register_algorithm


@dataclass(frozen=True)
class InverseKKTConfig:
    """Settings of the inverse-KKT fit.

    Attributes:
        active_tol: a constraint or bound within this of its bound counts as active. IPOPT
            stops inside the bounds, with a weakly active constraint's slack up to ~1e-6 and
            a multiplier that matters; measured on the four nominal-speed demonstrations,
            1e-7 left 0.003-0.02 weight error, 1e-6 up to 0.008, 1e-5 and 1e-4 below 2e-5.
        normalisation_weight: weight of the normalisation row relative to the stationarity
            rows (whose columns are scaled to unit norm).
        regularisation: Tikhonov term (relative) for the equality Jacobian's Gram matrix,
            used only if it is singular (measured: with 1e-10 always on, the elimination
            left a residual that cost 0.005-0.03 weight error in the ideal condition; with
            none, 1e-7).
    """

    active_tol: float = 1e-5
    normalisation_weight: float = 1e3
    regularisation: float = 1e-14

    def __post_init__(self) -> None:
        if not (self.active_tol > 0 and self.normalisation_weight > 0 and self.regularisation >= 0):
            raise ValueError("active_tol and normalisation_weight must be > 0, regularisation >= 0")


@register_algorithm("inverse-kkt")
class InverseKKT(IOCAlgorithm):
    """Weights minimising the KKT residual at the projected observation (bounded least squares)."""

    description = "inverse KKT: bounded least squares on the KKT residual at the projected observation"
    family = "inverse-kkt"
    Config = InverseKKTConfig

    def fit(self, problem: IOCProblem) -> IOCResult:
        cfg: InverseKKTConfig = self.config
        ref = problem.reference()
        if not ref.success:
            return IOCResult(np.full(problem.n_features, np.nan), f"failed: projection {ref.status}")
        view = problem.forward
        x = view.vector(ref.trajectory)
        columns, lower, upper, n_w = _columns(view, x, cfg.active_tol)
        equality = _equalities(view, x)
        projected = _project_out(equality, columns, cfg.regularisation)
        norms = np.maximum(np.linalg.norm(projected, axis=0), 1e-300)
        scaled = projected / norms
        row = np.zeros(scaled.shape[1])
        row[:n_w] = cfg.normalisation_weight  # sum of the weights in units of their own columns' norms
        a = np.vstack([scaled, row])
        b = np.zeros(a.shape[0])
        b[-1] = cfg.normalisation_weight
        fit = lsq_linear(a, b, bounds=(lower * norms, upper * norms), method="bvls")
        z = fit.x / norms
        w = np.maximum(z[:n_w], 0.0)
        if not np.any(w > 0):
            return IOCResult(np.full(problem.n_features, np.nan), "failed: all weights zero")
        residual = float(np.linalg.norm(projected @ z))
        scale = float(np.linalg.norm(projected[:, :n_w] @ w))
        notes = {
            "kkt_residual": residual,
            "relative_residual": residual / max(scale, 1e-300),
            "active_columns": int(a.shape[1] - n_w - 1),
            "lsq_status": int(fit.status),
        }
        return IOCResult(w / np.linalg.norm(w), "converged" if fit.success else f"failed: {fit.message}", notes=notes)


def _columns(view, x: np.ndarray, tol: float) -> tuple[np.ndarray, np.ndarray, np.ndarray, int]:
    """Dense (n_x, k) stationarity columns with their bounds: the weights' (``s dphi/dx^T``),
    the penalty gradient's, and one per active inequality and bound (sign-constrained)."""
    lbx, ubx = view.variable_bounds()
    lbg, ubg = view.constraint_bounds()
    g = view.constraints(x)
    weights = view.objective_scale * view.feature_jacobian(x).T.toarray()
    cols = [weights, view.regularizer_gradient(x)[:, None]]
    lower = [np.zeros(weights.shape[1]), [0.0]]
    upper = [np.full(weights.shape[1], np.inf), [np.inf]]
    jac = view.constraint_jacobian(x)
    inequality = lbg < ubg
    for values, lo, hi, matrix in ((g, lbg, ubg, jac.T.tocsc()), (x, lbx, ubx, sp.eye(x.size, format="csc"))):
        at_lo, at_hi = _sides(values, lo, hi, tol)
        if matrix.shape[1] == g.size:
            at_lo, at_hi = at_lo & inequality, at_hi & inequality
        for mask, lo_b, hi_b in ((at_lo, -np.inf, 0.0), (at_hi, 0.0, np.inf)):
            idx = np.flatnonzero(mask)
            if idx.size:
                cols.append(matrix[:, idx].toarray())
                lower.append(np.full(idx.size, lo_b))
                upper.append(np.full(idx.size, hi_b))
    return np.hstack(cols), np.concatenate(lower), np.concatenate(upper), weights.shape[1]


def _equalities(view, x: np.ndarray) -> sp.csr_matrix:
    lbg, ubg = view.constraint_bounds()
    return view.constraint_jacobian(x).tocsr()[lbg == ubg]


def _project_out(equality: sp.csr_matrix, columns: np.ndarray, regularisation: float) -> np.ndarray:
    """``columns`` minus their component in the row space of ``equality`` (whose multipliers
    are free, so any such component can be absorbed)."""
    gram = (equality @ equality.T).tocsc()
    try:
        lu = spla.splu(gram)
    except RuntimeError:  # dependent equality constraints: regularise
        scale = max(float(abs(gram).max()), 1.0)
        lu = spla.splu((gram + regularisation * scale * sp.eye(gram.shape[0])).tocsc())
    return columns - equality.T @ lu.solve(equality @ columns)


def _sides(values: np.ndarray, lower: np.ndarray, upper: np.ndarray, tol: float) -> tuple[np.ndarray, np.ndarray]:
    with np.errstate(invalid="ignore"):
        at_lo = np.isfinite(lower) & (values - lower <= tol * (1 + np.abs(lower)))
        at_hi = np.isfinite(upper) & (upper - values <= tol * (1 + np.abs(upper))) & ~at_lo
    return at_lo, at_hi
