"""The three IOC families from the literature recover the weights from an exact observation."""

from __future__ import annotations

import numpy as np
import pytest

import ioc_bench
from ioc_bench.ioc import describe_algorithms, get_algorithm


def test_families_are_registered():
    families = {name: get_algorithm(name).family for name in describe_algorithms()}
    assert families["inverse-kkt"] == "inverse-kkt"
    assert families["bilevel"] == "bilevel"
    assert families["single-level"] == "single-level"
    assert families["log-barrier"] == families["analytic-center"] == "cutting-plane"


@pytest.mark.parametrize("algorithm", ["inverse-kkt", "bilevel", "single-level"])
def test_recovers_penalize_knee_in_the_ideal_condition(algorithm, penalize_knee_cached):
    result = ioc_bench.run_case(algorithm, "penalize-knee", "ideal", seed=0)
    assert result.status == "converged", result.reason
    assert result.weight_error < 1e-3, (result.weights, result.true_weights)
    assert result.family == algorithm


def test_inverse_kkt_uses_one_projection_and_no_forward_solve(penalize_knee_cached):
    result = ioc_bench.run_case("inverse-kkt", "penalize-knee", "ideal", seed=0)
    assert result.oracle["calls"].get("project") == 1 and "optimize" not in result.oracle["calls"]
    assert result.notes["relative_residual"] < 1e-3
    assert result.found_trajectory_error is None  # no step of its own to report


@pytest.mark.parametrize("algorithm", ["inverse-kkt", "bilevel", "single-level", "log-barrier", "analytic-center"])
def test_every_built_in_reports_a_region_that_holds_an_exact_estimate(algorithm, penalize_knee_cached):
    result = ioc_bench.run_case(algorithm, "penalize-knee", "ideal", seed=0)
    region = result.uncertainty
    assert region is not None and region["method"], result.reason
    assert len(region["lower"]) == len(result.features)
    assert all(lo <= hi for lo, hi in zip(region["lower"], region["upper"]))
    assert all(lo - 1e-9 <= w <= hi + 1e-9 for lo, w, hi in zip(region["lower"], result.weights, region["upper"]))


def test_bilevel_gauss_newton_recovers_an_exact_observation_in_few_solves(penalize_knee_cached):
    result = ioc_bench.run_case("bilevel", "penalize-knee", "ideal", seed=0)
    assert result.weight_error < 1e-4 and result.n_solves <= 8, (result.weight_error, result.n_solves)
    assert result.covered  # exact data: the region holds the truth
    # L-BFGS-B (method lbfgs) is selectable and recovers exact data too. (On exact
    # data it needs no more solves than Gauss-Newton here; they differ under noise and distractors.)
    old = ioc_bench.run_case("bilevel", "penalize-knee", "ideal", seed=0, config={"method": "lbfgs"})
    assert old.status != "failed" and old.weight_error < 1e-3, (old.reason, old.weight_error)


def test_an_exact_estimate_transfers_to_the_other_speed(penalize_knee_cached):
    result = ioc_bench.run_case("inverse-kkt", "penalize-knee", "ideal", seed=0)
    assert result.weight_error < 1e-4
    assert result.transfer["speed"] == 0.34 and result.transfer["trajectory_error"] < 1e-4


@pytest.mark.parametrize("algorithm", ["inverse-kkt", "bilevel", "single-level"])
def test_multi_trial_ioc_explains_both_speeds_with_one_weight_vector(algorithm, penalize_knee_cached):
    result = ioc_bench.run_case(algorithm, "penalize-knee", "multi-speed", seed=0)
    assert result.status == "converged" and result.weight_error < 1e-3, (result.reason, result.weight_error)
    assert result.transfer is None  # both speeds are observed: none is left to transfer to
    assert len(result.scoring_status.split(", ")) == 2


def test_an_algorithm_without_multi_trial_support_is_recorded_as_failed(penalize_knee_cached):
    from ioc_bench import IOCAlgorithm, IOCResult
    from ioc_bench.ioc import registry

    class SingleOnly(IOCAlgorithm):
        def fit(self, problem):
            return IOCResult(np.ones(problem.n_features))

    registry._add("single-trial-only", SingleOnly, "test")
    try:
        result = ioc_bench.run_case("single-trial-only", "penalize-knee", "multi-speed", seed=0)
    finally:
        registry._REGISTRY.pop("single-trial-only")
    assert result.failed and "several trials" in result.reason


@pytest.mark.parametrize("algorithm", ["bilevel", "single-level"])
def test_a_fitted_model_of_exact_data_is_not_rejected(algorithm, penalize_knee_cached):
    """The misfit test of an exact observation: the residual is far below any noise."""
    result = ioc_bench.run_case(algorithm, "penalize-knee", "ideal", seed=0)
    assert result.misfit is False, result.model_fit
    assert result.model_fit["statistic"] < 1e-2 and result.model_fit["threshold"] > 1


def test_single_level_starts_at_a_kkt_point_and_ends_at_a_verified_optimum(penalize_knee_cached):
    """From the uniform start (not an exact fit) every stage is anchored by a forward solve of
    its weights, and the output is the last one."""
    result = ioc_bench.run_case("single-level", "penalize-knee", "ideal", seed=0, config={"init": "uniform"})
    stages = [h["extra"].get("stage") for h in result.history]
    assert stages[0] == "start" and stages[-1] == "anchor", stages
    assert result.chosen_iteration == len(result.history) - 1
    assert [s["relaxation"] for s in result.notes["solves"]] == [1e-3, 1e-6]
    assert result.notes["tracking_error"] < 1e-8 and result.weight_error < 1e-3


def test_single_level_returns_an_exact_start_without_solving_its_nlp(penalize_knee_cached):
    """The inverse-KKT start of exact data reproduces the observation: it is the answer."""
    from ioc_bench.ioc.single_level import EXACT_START

    result = ioc_bench.run_case("single-level", "penalize-knee", "ideal", seed=0)
    assert result.notes["solves"] == [] and "single_level_nlp" not in result.oracle["calls"]
    assert result.history[result.chosen_iteration]["extra"]["stage"] == "start"
    assert result.notes["tracking_error"] <= EXACT_START and result.weight_error < 1e-4


def test_single_level_ranks_further_starts_when_the_first_two_do_not_fit(penalize_knee_cached, monkeypatch):
    """When the better first start fails the misfit test, the starts of ``ioc/starts.py`` are
    solved and ranked with them (here the test is made to fail on exact data)."""
    from ioc_bench.ioc import single_level

    monkeypatch.setattr(single_level, "_fits", lambda problem, sols: False)
    result = ioc_bench.run_case("single-level", "penalize-knee", "ideal", seed=0)
    starts = [h for h in result.history if h["extra"].get("stage") == "start"]
    assert len(starts) == 2 + 1 + len(result.features), [h["weights"] for h in starts]
    assert result.weight_error < 1e-4  # the exact start still ranks first


def test_single_level_fits_two_noisy_trials_with_one_weight_vector_through_its_nlp(penalize_knee_cached):
    """Noisy trials leave no exact start, so the two-trial NLP runs (committed cell: 0.0018)."""
    result = ioc_bench.run_case("single-level", "penalize-knee", "multi-speed-noise", seed=0)
    assert [s["relaxation"] for s in result.notes["solves"]] == [1e-3, 1e-6], result.notes
    assert result.status == "converged" and result.weight_error < 0.01, (result.reason, result.weight_error)
    assert result.misfit is False, result.model_fit


@pytest.mark.parametrize("restarts", [-1, True, 1.5])
def test_single_level_refuses_restarts_that_are_not_a_count(restarts):
    from ioc_bench.ioc.single_level import SingleLevelConfig

    with pytest.raises(ValueError, match="restarts must be an integer >= 0"):
        SingleLevelConfig(restarts=restarts)
