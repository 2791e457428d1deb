"""The differentiable view: derivatives against finite differences, sensitivity against re-solves."""

from __future__ import annotations

import numpy as np
import pytest

from ioc_bench.features import COST_FEATURES
from ioc_bench.ioc.problem import IOCProblem


@pytest.fixture(scope="module")
def problem(nominal_demo) -> IOCProblem:
    return IOCProblem(nominal_demo.trajectory, COST_FEATURES, nominal_demo.params, nominal_demo.task)


def _directions(x: np.ndarray, view, n: int = 4) -> list[np.ndarray]:
    rng = np.random.default_rng(5)
    out = []
    for _ in range(n):
        d = rng.normal(size=x.size) * 1e-6
        d[view.blocks["dt"]] = d[view.blocks["dt"]][0]  # the spacing copies move together
        out.append(d)
    return out


def test_vector_and_trajectory_are_inverse(problem, nominal_demo):
    view = problem.forward
    x = view.vector(nominal_demo.trajectory)
    again = view.trajectory(x)
    np.testing.assert_allclose(again.q, nominal_demo.trajectory.q)
    np.testing.assert_allclose(again.tau, nominal_demo.trajectory.tau)
    np.testing.assert_allclose(view.vector(again), x)
    assert x[view.signal_indices] == pytest.approx(nominal_demo.trajectory.signals())


def test_derivatives_match_finite_differences(problem, nominal_demo):
    view = problem.forward
    x = view.vector(nominal_demo.trajectory)
    jac_g, jac_phi, grad_r = view.constraint_jacobian(x), view.feature_jacobian(x), view.regularizer_gradient(x)
    assert jac_g.shape == (view.n_g, view.n_x) and jac_phi.shape == (3, view.n_x)
    for d in _directions(x, view):
        dg = (view.constraints(x + d) - view.constraints(x - d)) / 2
        np.testing.assert_allclose(dg, jac_g @ d, rtol=1e-4, atol=1e-12)
        dphi = (view.features_at(x + d) - view.features_at(x - d)) / 2
        np.testing.assert_allclose(dphi, jac_phi @ d, rtol=1e-4, atol=1e-12)
        dr = (view.regularizer(x + d) - view.regularizer(x - d)) / 2
        assert dr == pytest.approx(grad_r @ d, rel=1e-4, abs=1e-14)
    hess = view.feature_hessian(x, "hip")
    d = _directions(x, view, 1)[0]
    grad_step = (view.feature_jacobian(x + d) - view.feature_jacobian(x - d))[0] / 2
    np.testing.assert_allclose(grad_step.toarray().ravel(), hess @ d, rtol=1e-4, atol=1e-10)


def test_sensitivity_matches_re_solves(problem):
    view = problem.forward
    w = np.ones(3) / np.sqrt(3)
    sol = problem.optimize(w)
    assert sol.success
    dx_dw = view.sensitivity(sol)
    lam_g, lam_x = view.duals(sol)
    assert lam_g.shape == (view.n_g,) and lam_x.shape == (view.n_x,)
    x0 = view.vector(sol.trajectory)
    for i in range(3):
        e = np.zeros(3)
        e[i] = 1e-4
        plus, minus = problem.optimize(w + e, start=sol), problem.optimize(w - e, start=sol)
        moved = (view.vector(plus.trajectory) - view.vector(minus.trajectory)) / 2
        # optimize() normalises the weights, so the step seen is e's part across w
        predicted = dx_dw @ (e - w * (w @ e))
        assert np.linalg.norm(moved - predicted) < 0.05 * np.linalg.norm(moved)
        assert np.linalg.norm(moved) > 1e-6 * np.linalg.norm(x0)  # the weights do move the optimum
    assert problem.stats.calls["sensitivity"] == 1 and problem.stats.calls["derivatives"] > 0


def test_tracking_error_gradient(problem, nominal_demo):
    view = problem.forward
    x = view.vector(nominal_demo.trajectory)
    rng = np.random.default_rng(1)
    y = x + rng.normal(size=x.size) * 1e-3
    e, g = view.tracking_error(y)
    assert e == pytest.approx(problem.tracking_error(view.trajectory(y)), rel=1e-9)
    d = rng.normal(size=x.size) * 1e-6
    assert (view.tracking_error(y + d)[0] - view.tracking_error(y - d)[0]) / 2 == pytest.approx(g @ d, rel=1e-5)
    ref, weight = view.tracking_quadratic()
    assert np.sum(weight * (y - ref) ** 2) == pytest.approx(e, rel=1e-9)
