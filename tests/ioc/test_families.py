"""The three IOC families from the literature recover the weights from an exact observation."""

from __future__ import annotations

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
