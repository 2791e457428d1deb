"""IOCProblem's oracles: a projection started warm at the reference is the cold one; a failed
projection of the observation is tried again from a feasible step."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from ioc_bench.features import COST_FEATURES
from ioc_bench.ioc.problem import IOCProblem
from ioc_bench.synthetic.observe import observe


@pytest.fixture(scope="module")
def problem(nominal_demo) -> IOCProblem:
    observed = observe(nominal_demo.trajectory, 0.02, np.random.default_rng(3))
    return IOCProblem(observed, COST_FEATURES, nominal_demo.params, nominal_demo.task, seed=4)


def test_a_warm_projection_of_a_perturbation_is_the_cold_one(problem):
    reference = problem.reference()
    assert reference.success
    rng, iterations = problem.rng(stream=1), np.zeros(2)
    for _ in range(2):
        target = problem.perturb(rng, 0.05)
        cold, warm = problem.project(target), problem.project(target, start=reference)
        assert cold.success and warm.success
        np.testing.assert_allclose(warm.features, cold.features, rtol=1e-6)
        np.testing.assert_allclose(warm.trajectory.q, cold.trajectory.q, atol=1e-6)
        assert not np.allclose(warm.features, reference.features, rtol=1e-4)  # a different step
        iterations += (cold.report.iterations, warm.report.iterations)
    assert iterations[1] < iterations[0]  # the start was used: the same point, reached sooner


def test_a_projection_start_that_is_not_a_solution_is_refused(problem, nominal_demo):
    for start in ("warm", 3, nominal_demo.trajectory):
        with pytest.raises(ValueError, match="start must be an OracleSolution"):
            problem.project(problem.observed, start=start)


def _failing_cold_projection(problem: IOCProblem, always: bool = False) -> list:
    """Make ``problem``'s cold projections (and, if ``always``, every projection) report
    failure at the point they reached; returns the list of starts each call was given."""
    real, calls = problem.project, []

    def project(target, start=None):
        calls.append(start)
        found = real(target, start)
        if start is not None and not always:
            return found
        return replace(found, success=False, report=replace(found.report, status="Restoration_Failed", success=False))

    problem.project = project
    return calls


def test_a_failed_projection_of_the_observation_is_retried_from_a_feasible_step(nominal_demo):
    truth = IOCProblem(
        observe(nominal_demo.trajectory, 0.0, None), COST_FEATURES, nominal_demo.params, nominal_demo.task
    )
    problem = IOCProblem(truth.observed, COST_FEATURES, nominal_demo.params, nominal_demo.task)
    calls = _failing_cold_projection(problem)
    reference = problem.reference()
    assert reference.success and len(calls) == 2 and calls[0] is None and calls[1] is not None
    np.testing.assert_allclose(reference.features, truth.reference().features, rtol=1e-6)


def test_a_projection_that_fails_again_is_the_reference_that_failed(nominal_demo):
    problem = IOCProblem(
        observe(nominal_demo.trajectory, 0.0, None), COST_FEATURES, nominal_demo.params, nominal_demo.task
    )
    calls = _failing_cold_projection(problem, always=True)
    reference = problem.reference()
    assert not reference.success and reference.report.status == "Restoration_Failed" and len(calls) == 2


def test_a_problem_may_weigh_features_outside_the_default_basis(nominal_demo):
    """Work and collision are weighed by name: the problem's forward basis holds them, its
    features are the evaluated ones, and weighing work moves the optimum to less work."""
    from ioc_bench.bases import forward_basis
    from ioc_bench.features import evaluate, model_features
    from ioc_bench.model.walker import WALKER

    features = ("hip", "knee", "dtau", "work", "collision")
    assert forward_basis(WALKER, features) == (*model_features(WALKER), "work", "collision")
    assert forward_basis(WALKER, COST_FEATURES) is None
    problem = IOCProblem(nominal_demo.trajectory, features, nominal_demo.params, nominal_demo.task)
    values = evaluate(nominal_demo.trajectory, nominal_demo.params, features)
    np.testing.assert_allclose(problem.features_of(nominal_demo.trajectory), [values[f] for f in features])
    mine = problem.optimize(np.array([1.0, 1.0, 1.0, 20.0, 0.0]), start=nominal_demo.trajectory)
    assert mine.success
    there = evaluate(mine.trajectory, nominal_demo.params, features)
    np.testing.assert_allclose(mine.features, [there[f] for f in features], rtol=1e-9)
    assert there["work"] < 0.9 * values["work"]  # the nominal step is not this cost's optimum


def test_a_feature_the_model_lacks_is_refused_naming_the_models_features(nominal_demo):
    with pytest.raises(ValueError, match=r"has no feature.*'ankle'.*it has: hip, knee"):
        IOCProblem(nominal_demo.trajectory, ("hip", "ankle"), nominal_demo.params, nominal_demo.task)
