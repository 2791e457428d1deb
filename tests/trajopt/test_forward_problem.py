"""The forward problem: solver reports, warm starts, failures recorded as results, its maps."""

from __future__ import annotations

import casadi as ca
import numpy as np
import pytest

from ioc_bench import Task, optimize_gait
from ioc_bench.model.params import WalkerParams
from ioc_bench.model.walker import WALKER
from ioc_bench.trajopt.forward_problem import ForwardProblem, SolveRequest, get_forward_problem
from ioc_bench.trajopt.initial_guess import rough_step
from ioc_bench.trajopt.solution import FEASIBILITY_TOL, StartPoint
from ioc_bench.weights import full_weights, parse_weights


def test_report_fields(nominal_demo):
    s = nominal_demo.solver
    assert s.success and s.status == "Solve_Succeeded"
    assert s.max_violation <= FEASIBILITY_TOL and s.iterations > 0 and s.wall_time > 0
    phi = [nominal_demo.features[f] for f in ("hip", "knee", "dtau")]
    assert s.objective == pytest.approx(np.dot(nominal_demo.weight_vector, phi), rel=1e-9)


def test_warm_start_from_a_demonstration_is_fast_and_consistent(nominal_demo):
    again = optimize_gait("nominal", init=nominal_demo)
    assert again.solver.success and again.solver.warm
    assert again.solver.iterations <= 5
    assert again.solver.objective == pytest.approx(nominal_demo.solver.objective, rel=1e-6)
    nearby = optimize_gait("1.1,1,1", init=nominal_demo)
    assert nearby.solver.success and nearby.solver.iterations < nominal_demo.solver.iterations


def test_failed_solve_is_a_result_not_an_exception(nominal_demo):
    forward = get_forward_problem(n_intervals=nominal_demo.n_intervals)
    x0 = forward.vector(nominal_demo.trajectory)
    # An impossible task: faster than the step-time bounds allow.
    weights = full_weights(parse_weights("nominal"), ("hip", "knee", "dtau"))
    result = forward.solve(SolveRequest(StartPoint(x0), nominal_demo.params, Task(50.0), weights))
    assert not result.report.success
    assert result.report.status != "Solve_Succeeded" or result.report.max_violation > FEASIBILITY_TOL
    demo = optimize_gait("nominal", task=Task(50.0), starts=1, workers=1)
    assert not demo.solver.success  # still a demonstration, flagged infeasible


def test_weak_lock_penalty_is_repaired(nominal_demo):
    """With penalty 1 the optimum lets the lock 'kick' (products ~1e-2); the solver notices
    and re-solves with a stronger penalty instead of returning an invalid step."""
    forward = get_forward_problem(n_intervals=nominal_demo.n_intervals)
    start = StartPoint(forward.vector(nominal_demo.trajectory))
    weights = full_weights(parse_weights("nominal"), ("hip", "knee", "dtau"))
    result = forward.solve(SolveRequest(start, nominal_demo.params, Task(0.27), weights, lock_penalty=1.0))
    assert result.report.repaired
    assert result.report.success and result.report.complementarity <= 1e-6


def test_trajectory_and_vector_are_inverse_maps(nominal_demo):
    forward = get_forward_problem(n_intervals=nominal_demo.n_intervals)
    x = forward.vector(nominal_demo.trajectory)
    again = forward.trajectory(x, nominal_demo.params)
    assert np.array_equal(forward.vector(again), x)
    assert np.allclose(again.acc, nominal_demo.trajectory.acc, atol=1e-12)


def test_a_solve_from_its_own_solution_stays_there(nominal_demo):
    """A warm start at a demonstration's primal-dual point returns it (the request's fields
    reach the solver: weights, params, task)."""
    forward = get_forward_problem(n_intervals=nominal_demo.n_intervals)
    weights = full_weights(parse_weights("nominal"), forward.features)
    start = StartPoint(forward.vector(nominal_demo.trajectory), nominal_demo.lam_x, nominal_demo.lam_g)
    result = forward.solve(SolveRequest(start, nominal_demo.params, nominal_demo.task, weights))
    assert result.report.success and result.report.iterations <= 3
    assert np.max(np.abs(result.x - start.x)) < 1e-5  # measured 2e-6 (a velocity)
    assert result.report.objective == pytest.approx(nominal_demo.solver.objective, rel=1e-7)
    other = forward.solve(SolveRequest(start, nominal_demo.params, nominal_demo.task, weights[::-1].copy()))
    assert np.max(np.abs(other.x - start.x)) > 1e-2  # other weights: another optimum


def test_the_cold_solvers_lock_scaling_is_a_change_of_variables_only():
    """The cold solver works on scaled lock torques; the optimum it returns, and its
    multipliers, are those of the NLP itself (the same optimum as without the scaling, and
    the NLP's own KKT conditions hold in its own variables)."""
    scaled = get_forward_problem()
    plain = ForwardProblem(lock_scale=1.0)
    weights = full_weights(parse_weights("nominal"), scaled.features)
    x0 = scaled.step.layout.pack(rough_step(WALKER, WalkerParams(), 0.27, scaled.n_knots))
    request = SolveRequest(StartPoint(x0), WalkerParams(), Task(0.27), weights)
    a, b = scaled.solve(request), plain.solve(request)
    assert a.report.success and b.report.success and not a.report.warm
    assert a.report.objective == pytest.approx(b.report.objective, rel=1e-7)
    assert np.max(np.abs(a.x - b.x)) < 1e-5
    nlp = scaled.step.casadi_nlp
    kkt = ca.Function("kkt", [nlp["x"], nlp["p"]], [ca.gradient(nlp["f"], nlp["x"]), ca.jacobian(nlp["g"], nlp["x"])])
    p = scaled.parameters(WalkerParams(), Task(0.27), weights)
    grad, jac = (np.asarray(m.full() if hasattr(m, "full") else m, dtype=float) for m in kkt(a.x, p))
    residual = grad.ravel() + jac.T @ a.lam_g + a.lam_x
    assert np.max(np.abs(residual)) < 1e-6
