"""Derivatives of the step problem at any point, and of its optima with respect to the weights.

The NLP is ``min_x s w . phi(x) + R(x) + T(x)  s.t.  lbg <= g(x) <= ubg, lbx <= x <= ubx`` (R the
lock penalty, T a tracking term, both off unless asked for). Its constraint Jacobian and
Lagrangian Hessian are the solver's own (``nlp_jac_g``, ``nlp_hess_l`` of the built IPOPT
instance); the feature and penalty derivatives are built from the same symbolic expressions
on first use.

The sensitivity of an optimum ``x*(w)`` follows from the KKT conditions with the active set
held fixed (the implicit-function theorem; Fiacco 1976, as used by PDP and IDOC):

    [ H   A^T ] [ dx/dw ]   [ -d(grad_x L)/dw ]
    [ A  -dI  ] [ dnu/dw] = [        0        ]

with ``A`` the Jacobian of the equality constraints, the active inequalities and the active
bounds, and a tiny ``d`` keeping the system solvable where active constraints are dependent.
"""

from __future__ import annotations

from collections.abc import Callable
from functools import cached_property

import casadi as ca
import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from ioc_bench.trajopt.active_set import ActiveSet
from ioc_bench.trajopt.step_problem import StepProblem

#: (lbx, ubx, lbg, ubg) of one solve.
Bounds = tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]

#: A constraint or bound within this (absolute, plus relative to its bound) is active at an
#: optimum (IPOPT's solutions hold their active constraints to ~1e-9).
ACTIVE_TOL = 1e-7
#: Regularisation of the KKT system's lower-right block (dependent active constraints).
KKT_REGULARISATION = 1e-10


def to_sparse(m: ca.DM) -> sp.csc_matrix:
    """A CasADi sparse matrix as a SciPy one (structural zeros stay out)."""
    rows, cols = m.sparsity().get_triplet()
    return sp.csc_matrix((np.asarray(m.nonzeros(), dtype=float), (rows, cols)), shape=m.shape)


class StepDerivatives:
    """Numeric derivatives of a step NLP (``ForwardProblem.derivatives``).

    Args:
        step: the transcribed NLP.
        oracle: the built IPOPT instance's own functions by name (``nlp_jac_g``, ``nlp_hess_l``),
            so the derivatives are exactly the ones the solver uses.
    """

    def __init__(self, step: StepProblem, oracle: Callable[[str], ca.Function]):
        self.step = step
        self._oracle = oracle

    # -- functions, built on first use ------------------------------------------------------
    @cached_property
    def _jac_g(self) -> ca.Function:
        return self._oracle("nlp_jac_g")

    @cached_property
    def _hess_l(self) -> ca.Function:
        return self._oracle("nlp_hess_l")

    @cached_property
    def _symbols(self) -> tuple[ca.SX, ca.SX]:
        return self.step.casadi_nlp["x"], self.step.casadi_nlp["p"]

    @cached_property
    def _jac_phi(self) -> ca.Function:
        x, p = self._symbols
        return ca.Function("jac_phi", [x, p], [ca.jacobian(self.step.features_fn(x, p), x)])

    @cached_property
    def _grad_reg(self) -> ca.Function:
        x, p = self._symbols
        return ca.Function("grad_reg", [x, p], [ca.gradient(self.step.regularizer_fn(x, p), x)])

    @cached_property
    def _basis_jac(self) -> ca.Function:
        x, p = self._symbols
        return ca.Function("basis_jac", [x, p], [ca.jacobian(self.step.weight_basis, x)])

    def _hess_phi(self, index: int) -> ca.Function:
        x, p = self._symbols
        h, _ = ca.hessian(self.step.features_fn(x, p)[index], x)
        return ca.Function(f"hess_phi_{index}", [x, p], [h])

    # -- values ------------------------------------------------------------------------------
    def constraints(self, x: np.ndarray, p: np.ndarray) -> np.ndarray:
        return np.asarray(self.step.g_fn(x, p), dtype=float).ravel()

    def constraint_jacobian(self, x: np.ndarray, p: np.ndarray) -> sp.csc_matrix:
        return to_sparse(self._jac_g(x, p)[1])

    def features(self, x: np.ndarray, p: np.ndarray) -> np.ndarray:
        return np.asarray(self.step.features_fn(x, p), dtype=float).ravel()

    def feature_jacobian(self, x: np.ndarray, p: np.ndarray) -> sp.csc_matrix:
        return to_sparse(self._jac_phi(x, p))

    def feature_hessian(self, x: np.ndarray, p: np.ndarray, index: int) -> sp.csc_matrix:
        return to_sparse(self._hess_phi(index)(x, p))

    def regularizer(self, x: np.ndarray, p: np.ndarray) -> float:
        return float(self.step.regularizer_fn(x, p))

    def regularizer_gradient(self, x: np.ndarray, p: np.ndarray) -> np.ndarray:
        return np.asarray(self._grad_reg(x, p), dtype=float).ravel()

    def weight_jacobian(self, x: np.ndarray, p: np.ndarray) -> sp.csc_matrix:
        """(n_x, F) derivative of the objective's gradient by the weights (``s * dphi/dx^T``)."""
        return to_sparse(self._basis_jac(x, p)).T.tocsc()

    def lagrangian_hessian(self, x: np.ndarray, p: np.ndarray, lam_g: np.ndarray) -> sp.csc_matrix:
        """Symmetric Hessian of ``f + lam_g . g`` (the solver gives the upper triangle)."""
        upper = to_sparse(self._hess_l(x, p, 1.0, lam_g))
        return (upper + upper.T - sp.diags(upper.diagonal())).tocsc()

    # -- active set and sensitivity -------------------------------------------------------------
    def active_set(self, x: np.ndarray, p: np.ndarray, bounds: Bounds, tol: float = ACTIVE_TOL) -> ActiveSet:
        """Active constraints and bounds at ``x`` (``bounds`` = lbx, ubx, lbg, ubg)."""
        return ActiveSet.at(x, self.constraints(x, p), bounds, tol)

    def sensitivity(self, x: np.ndarray, p: np.ndarray, lam_g: np.ndarray, active: ActiveSet) -> np.ndarray:
        """(n_x, F) derivative of the optimum by the weights, active set held fixed."""
        h = self.lagrangian_hessian(x, p, lam_g)
        jac = self.constraint_jacobian(x, p)[active.constraints]
        fixed = sp.eye(x.size, format="csr")[active.bounds]
        a = sp.vstack([jac, fixed]).tocsc()
        m = a.shape[0]
        kkt = sp.bmat([[h, a.T], [a, -KKT_REGULARISATION * sp.eye(m)]], format="csc")
        rhs = np.vstack(
            [-self.weight_jacobian(x, p).toarray(), np.zeros((m, self.step.params.blocks["weights"][1][0]))]
        )
        return spla.splu(kkt).solve(rhs)[: x.size]
