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
from typing import Any

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla
from scipy.optimize import lsq_linear

from ioc_bench.ioc.algorithm import IOCAlgorithm, IOCResult, WeightRegion
from ioc_bench.ioc.problem import IOCProblem
from ioc_bench.ioc.registry import register_algorithm
from ioc_bench.trajopt.active_set import ActiveSet

#: z-value of a 95 % interval.
Z95 = 1.959963984540054
#: The least half-width of a weight's interval: below it the weights are not resolved (the
#: demonstrations are optimal only to 1e-6 in relative cost, which moves unit weights by up
#: to about 1e-4, and estimates of exact observations differ from the truth by up to 3e-4).
RESOLUTION = 1e-3


def interval(weights: np.ndarray, sd: np.ndarray) -> tuple[tuple[float, ...], tuple[float, ...]]:
    """The 95 % per-weight interval ``w +- max(1.96 sd, RESOLUTION)``, clipped to [0, 1]."""
    half = np.maximum(Z95 * sd, RESOLUTION)
    return tuple(np.clip(weights - half, 0.0, 1.0)), tuple(np.clip(weights + half, 0.0, 1.0))


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
        covariance: (F, F) covariance of the unit-norm weights from the fit's residual
            (see :func:`_weight_covariance`), None if it cannot be formed.
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
    covariance: np.ndarray | None = None


@dataclass(frozen=True, eq=False)
class _Blocks:
    """The stationarity system at one point, the equality multipliers eliminated.

    ``projected`` has a column per weight, one for the penalty's coefficient, then one per
    sign-constrained multiplier (``groups``: active lower and upper constraint sides, active
    lower and upper bounds), bounded by ``lower``/``upper``.
    """

    columns: np.ndarray
    projected: np.ndarray
    lower: np.ndarray
    upper: np.ndarray
    groups: list[np.ndarray]
    equality: sp.csr_matrix
    lu: object
    active: ActiveSet
    n_g: int
    equality_rows: np.ndarray


def _blocks(view, x: np.ndarray, cfg: InverseKKTConfig) -> _Blocks:
    lbg, ubg = view.constraint_bounds()
    active = view.active_set(x, cfg.active_tol)
    jac = view.constraint_jacobian(x)
    jac_t = jac.T.tocsc()
    eye = sp.eye(x.size, format="csc")
    weights = view.objective_scale * view.feature_jacobian(x).T.toarray()
    n_w = weights.shape[1]
    blocks = [
        (weights, np.zeros(n_w), np.full(n_w, np.inf)),
        (view.regularizer_gradient(x)[:, None], [0.0], [np.inf]),
    ]
    groups = []  # indices of each signed multiplier group
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
    equality = jac.tocsr()[lbg == ubg]
    lu = _gram_factor(equality, cfg.regularisation)
    return _Blocks(
        columns=columns,
        projected=columns - equality.T @ lu.solve(equality @ columns),
        lower=np.concatenate([np.asarray(b[1], dtype=float) for b in blocks]),
        upper=np.concatenate([np.asarray(b[2], dtype=float) for b in blocks]),
        groups=groups,
        equality=equality,
        lu=lu,
        active=active,
        n_g=lbg.size,
        equality_rows=lbg == ubg,
    )


@dataclass(frozen=True, eq=False)
class _Normalised:
    """The bounded least squares of the KKT residual, columns scaled to unit norm, with
    the normalisation row (the weights sum to 1 in those units): system, fit, solution."""

    a: np.ndarray
    b: np.ndarray
    norms: np.ndarray
    fit: Any
    z: np.ndarray


def _normalised_fit(
    projected: np.ndarray, lower: np.ndarray, upper: np.ndarray, n_w: int, cfg: InverseKKTConfig
) -> _Normalised:
    norms = np.maximum(np.linalg.norm(projected, axis=0), 1e-300)
    row = np.zeros(projected.shape[1])
    row[:n_w] = cfg.normalisation_weight
    a = np.vstack([projected / norms, row])
    b = np.zeros(a.shape[0])
    b[-1] = cfg.normalisation_weight
    fit = lsq_linear(a, b, bounds=(lower * norms, upper * norms), method="bvls")
    return _Normalised(a, b, norms, fit, fit.x / norms)


def fit_kkt(view, x: np.ndarray, cfg: InverseKKTConfig) -> KKTFit:
    """The inverse-KKT least-squares fit at decision vector ``x`` of a :class:`ForwardView`."""
    blk = _blocks(view, x, cfg)
    n_w = len(view.features)
    projected = blk.projected
    system = _normalised_fit(projected, blk.lower, blk.upper, n_w, cfg)
    fit, norms, z = system.fit, system.norms, system.z
    nu, lam = np.zeros(blk.n_g), np.zeros(x.size)
    offset = n_w + 1
    for k, idx in enumerate(blk.groups):
        target = nu if k < 2 else lam
        target[idx] += z[offset : offset + idx.size]
        offset += idx.size
    nu[blk.equality_rows] = -blk.lu.solve(blk.equality @ (blk.columns @ z))  # the eliminated equality multipliers
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
        active=blk.active,
        residual=residual,
        relative_residual=residual / max(scale, 1e-300),
        success=bool(fit.success) and bool(np.any(raw > 0)),
        covariance=_weight_covariance(system.a, system.b, fit, norms, n_w),
    )


@dataclass(frozen=True)
class JointFit:
    """One weight vector fitted to the stationarity of several trials at once.

    Attributes:
        weights: (F,) unit-norm weights.
        covariance: (F, F) their least-squares covariance, or None.
        relative_residual: the stacked residual over the norm of the weights' columns.
        success: the least-squares solver converged.
    """

    weights: np.ndarray
    covariance: np.ndarray | None
    relative_residual: float
    success: bool


def fit_kkt_trials(trials, cfg: InverseKKTConfig) -> JointFit:
    """The inverse-KKT fit of every trial's reference at once: shared weights and penalty
    coefficient, each trial's own multipliers (the rows stacked, the multipliers' columns
    block-diagonal); one trial gives :func:`fit_kkt`'s weights."""
    if len(trials) == 1:
        view = trials[0].forward
        one = fit_kkt(view, view.vector(trials[0].reference().trajectory), cfg)
        return JointFit(one.weights, one.covariance, one.relative_residual, one.success)
    blocks = [_blocks(t.forward, t.forward.vector(t.reference().trajectory), cfg) for t in trials]
    n_w = len(trials[0].features)
    shared = np.vstack([b.projected[:, : n_w + 1] for b in blocks])
    own = sp.block_diag([sp.csr_matrix(b.projected[:, n_w + 1 :]) for b in blocks]).toarray()
    projected = np.hstack([shared, own])
    lower = np.concatenate([blocks[0].lower[: n_w + 1], *[b.lower[n_w + 1 :] for b in blocks]])
    upper = np.concatenate([blocks[0].upper[: n_w + 1], *[b.upper[n_w + 1 :] for b in blocks]])
    system = _normalised_fit(projected, lower, upper, n_w, cfg)
    z = system.z
    raw = np.maximum(z[:n_w], 0.0)
    scale = float(np.linalg.norm(projected[:, :n_w] @ raw))
    return JointFit(
        weights=raw / max(np.linalg.norm(raw), 1e-300),
        covariance=_weight_covariance(system.a, system.b, system.fit, system.norms, n_w),
        success=bool(system.fit.success) and bool(np.any(raw > 0)),
        relative_residual=float(np.linalg.norm(projected @ z)) / max(scale, 1e-300),
    )


@register_algorithm("inverse-kkt")
class InverseKKT(IOCAlgorithm):
    """Weights minimising the KKT residual at the projected observation (bounded least squares)."""

    description = "inverse KKT: bounded least squares on the KKT residual at the projected observation"
    family = "inverse-kkt"
    multi_trial = True
    Config = InverseKKTConfig

    def fit(self, problem: IOCProblem) -> IOCResult:
        failed = [t.reference() for t in problem.trials if not t.reference().success]
        if failed:
            return IOCResult(np.full(problem.n_features, np.nan), f"failed: projection {failed[0].status}")
        if len(problem.trials) > 1:
            with problem.stats.timed("kkt_fit"):
                joint = fit_kkt_trials(problem.trials, self.config)
            notes = {"relative_residual": joint.relative_residual, "trials": len(problem.trials)}
            if not joint.success:
                return IOCResult(
                    np.full(problem.n_features, np.nan), "failed: the least-squares fit failed", notes=notes
                )
            return IOCResult(joint.weights, "converged", notes=notes, uncertainty=_region(joint))
        ref = problem.reference()
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
        return IOCResult(fit.weights, "converged", notes=notes, uncertainty=_region(fit))


def _region(fit: KKTFit | JointFit) -> WeightRegion | None:
    """The 95 % per-weight intervals of the fit's residual covariance (clipped to [0, 1])."""
    if fit.covariance is None:
        return None
    lower, upper = interval(fit.weights, np.sqrt(np.maximum(np.diag(fit.covariance), 0.0)))
    method = "least-squares covariance of the KKT residual at the reference"
    return WeightRegion(tuple(lower), tuple(upper), 0.95, tuple(map(tuple, fit.covariance)), method)


def _weight_covariance(a: np.ndarray, b: np.ndarray, fit, norms: np.ndarray, n_w: int) -> np.ndarray | None:
    """The least-squares covariance of the unit-norm weights: ``s^2 (A_f^T A_f)^{-1}`` over the
    free (not at a bound) unknowns, ``s^2`` the residual variance, mapped through the column
    scaling and the normalisation to unit norm. It treats the stationarity residual as
    independent noise, which it is not (a projection's residual is systematic); the
    leaderboard measures how that calibrates."""
    free = fit.active_mask == 0
    raw = fit.x[:n_w] / norms[:n_w]
    if not free[:n_w].any() or np.linalg.norm(raw) == 0:
        return None
    af = a[:, free]
    dof = max(a.shape[0] - int(free.sum()), 1)
    variance = float(np.sum((a @ fit.x - b) ** 2)) / dof
    cov_scaled = np.zeros((a.shape[1], a.shape[1]))
    cov_scaled[np.ix_(free, free)] = variance * np.linalg.pinv(af.T @ af)
    scale = 1.0 / norms[:n_w]
    cov_raw = cov_scaled[:n_w, :n_w] * np.outer(scale, scale)
    length = float(np.linalg.norm(raw))
    u = raw / length
    jac = (np.eye(n_w) - np.outer(u, u)) / length
    cov = jac @ cov_raw @ jac.T
    return (cov + cov.T) / 2


def _gram_factor(equality: sp.csr_matrix, regularisation: float):
    """Sparse LU of ``E E^T`` (regularised only if singular: dependent equality constraints)."""
    gram = (equality @ equality.T).tocsc()
    try:
        return spla.splu(gram)
    except RuntimeError:
        scale = max(float(abs(gram).max()), 1.0)
        return spla.splu((gram + regularisation * scale * sp.eye(gram.shape[0])).tocsc())
