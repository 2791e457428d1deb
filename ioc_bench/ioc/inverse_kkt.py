"""Inverse KKT: the weights under which the observed step best satisfies the optimality conditions.

After Puydupin-Jamin, Johnson & Bretl, "A convex approach to inverse optimal control and
its application to modeling human locomotion" (ICRA 2012), and Englert, Vien & Toussaint,
"Inverse KKT: Learning cost functions of manipulation tasks from demonstrations" (IJRR
2017). At the observation projected onto the IOC's model and task, ``x^``, the forward
problem's stationarity condition (``problem.forward``, IPOPT's sign convention)::

    s J_phi(x^)^T w + c grad R(x^) + J_g(x^)^T nu + lam = 0

is linear in the weights ``w``, the penalty's coefficient ``c`` and the multipliers ``nu``
(constraints) and ``lam`` (bounds). With ``x^``'s active set, equality constraints have free
multipliers, active inequalities and bounds sign-constrained ones, inactive ones none. The
algorithm minimises the residual's squared norm over ``w >= 0``, ``c >= 0`` and the
multipliers: a bounded linear least-squares problem (``scipy.optimize.lsq_linear``). The
free multipliers are eliminated first by projecting onto the complement of the equality
Jacobian's row space (one sparse factorisation), which leaves a column per weight, per
active inequality and per active bound. The weights are normalised in units of their own
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
from ioc_bench.trajopt.active_set import ActiveSet


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
            left a residual that cost 0.005-0.03 weight error in the ideal condition).
    """

    active_tol: float = 1e-5
    normalisation_weight: float = 1e3
    regularisation: float = 1e-14

    def __post_init__(self) -> None:
        if not (self.active_tol > 0 and self.normalisation_weight > 0 and self.regularisation >= 0):
            raise ValueError("active_tol and normalisation_weight must be > 0, regularisation >= 0")


@dataclass(frozen=True)
class KKTFit:
    """The least-squares KKT solution at a point.

    Attributes:
        weights: (F,) unit-norm weights over the problem's features.
        raw_weights: (F,) the weights as fitted, with ``normalisation . raw_weights = 1``.
        normalisation: (F,) each feature's projected gradient norm (its weight's unit).
        penalty: the coefficient of the lock penalty's gradient.
        nu: (n_g,) constraint multipliers (0 for inactive inequalities).
        lam: (n_x,) bound multipliers (0 for inactive bounds).
        active: the active set used (``forward.active_set`` at ``active_tol``).
        residual: norm of the stationarity residual at the fit.
        relative_residual: ``residual`` over the norm of the weights' projected columns.
        success: the least-squares solver converged.
    """

    weights: np.ndarray
    raw_weights: np.ndarray
    normalisation: np.ndarray
    penalty: float
    nu: np.ndarray
    lam: np.ndarray
    active: ActiveSet
    residual: float
    relative_residual: float
    success: bool


def fit_kkt(view, x: np.ndarray, cfg: InverseKKTConfig) -> KKTFit:
    """The inverse-KKT least-squares fit at decision vector ``x`` of a :class:`ForwardView`."""
    lbg, ubg = view.constraint_bounds()
    g = view.constraints(x)
    active = view.active_set(x, cfg.active_tol)
    jac_t = view.constraint_jacobian(x).T.tocsc()
    eye = sp.eye(x.size, format="csc")
    weights = view.objective_scale * view.feature_jacobian(x).T.toarray()
    n_w = weights.shape[1]
    blocks = [
        (weights, np.zeros(n_w), np.full(n_w, np.inf)),
        (view.regularizer_gradient(x)[:, None], [0.0], [np.inf]),
    ]
    groups = []  # (matrix, indices, lower, upper) of each signed multiplier group
    for matrix, mask, lo, hi in (
        (jac_t, active.g_lower, -np.inf, 0.0),
        (jac_t, active.g_upper, 0.0, np.inf),
        (eye, active.x_lower, -np.inf, 0.0),
        (eye, active.x_upper, 0.0, np.inf),
    ):
        idx = np.flatnonzero(mask)
        groups.append(idx)
        blocks.append((matrix[:, idx].toarray(), np.full(idx.size, lo), np.full(idx.size, hi)))
    columns = np.hstack([b[0] for b in blocks])
    lower = np.concatenate([np.asarray(b[1], dtype=float) for b in blocks])
    upper = np.concatenate([np.asarray(b[2], dtype=float) for b in blocks])
    equality = view.constraint_jacobian(x).tocsr()[lbg == ubg]
    lu = _gram_factor(equality, cfg.regularisation)
    projected = columns - equality.T @ lu.solve(equality @ columns)
    norms = np.maximum(np.linalg.norm(projected, axis=0), 1e-300)
    row = np.zeros(columns.shape[1])
    row[:n_w] = cfg.normalisation_weight
    a = np.vstack([projected / norms, row])
    b = np.zeros(a.shape[0])
    b[-1] = cfg.normalisation_weight
    fit = lsq_linear(a, b, bounds=(lower * norms, upper * norms), method="bvls")
    z = fit.x / norms
    nu, lam = np.zeros(g.size), np.zeros(x.size)
    offset = n_w + 1
    for k, idx in enumerate(groups):
        target = nu if k < 2 else lam
        target[idx] += z[offset : offset + idx.size]
        offset += idx.size
    nu[lbg == ubg] = -lu.solve(equality @ (columns @ z))  # the eliminated equality multipliers
    raw = np.maximum(z[:n_w], 0.0)
    residual = float(np.linalg.norm(projected @ z))
    scale = float(np.linalg.norm(projected[:, :n_w] @ raw))
    return KKTFit(
        weights=raw / max(np.linalg.norm(raw), 1e-300),
        raw_weights=raw,
        normalisation=norms[:n_w],
        penalty=float(z[n_w]),
        nu=nu,
        lam=lam,
        active=active,
        residual=residual,
        relative_residual=residual / max(scale, 1e-300),
        success=bool(fit.success) and bool(np.any(raw > 0)),
    )


@register_algorithm("inverse-kkt")
class InverseKKT(IOCAlgorithm):
    """Weights minimising the KKT residual at the projected observation (bounded least squares)."""

    description = "inverse KKT: bounded least squares on the KKT residual at the projected observation"
    family = "inverse-kkt"
    Config = InverseKKTConfig

    def fit(self, problem: IOCProblem) -> IOCResult:
        ref = problem.reference()
        if not ref.success:
            return IOCResult(np.full(problem.n_features, np.nan), f"failed: projection {ref.status}")
        view = problem.forward
        with problem.stats.timed("kkt_fit"):
            fit = fit_kkt(view, view.vector(ref.trajectory), self.config)
        notes = {
            "kkt_residual": fit.residual,
            "relative_residual": fit.relative_residual,
            "active_constraints": int(fit.active.g_lower.sum() + fit.active.g_upper.sum()),
            "active_bounds": int(fit.active.x_lower.sum() + fit.active.x_upper.sum()),
        }
        if not fit.success:
            return IOCResult(np.full(problem.n_features, np.nan), "failed: the least-squares fit failed", notes=notes)
        return IOCResult(fit.weights, "converged", notes=notes)


def _gram_factor(equality: sp.csr_matrix, regularisation: float):
    """Sparse LU of ``E E^T`` (regularised only if singular: dependent equality constraints)."""
    gram = (equality @ equality.T).tocsc()
    try:
        return spla.splu(gram)
    except RuntimeError:
        scale = max(float(abs(gram).max()), 1.0)
        return spla.splu((gram + regularisation * scale * sp.eye(gram.shape[0])).tocsc())
