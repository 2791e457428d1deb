"""The built-in algorithms on real cases: the paper's method runs; the variant recovers weights."""

from __future__ import annotations

import numpy as np
import pytest

import ioc_bench
from ioc_bench.ioc.log_barrier import LogBarrierConfig


def test_log_barrier_defaults_are_the_paper():
    cfg = LogBarrierConfig()
    assert (cfg.offset, cfg.lower, cfg.upper, cfg.max_iterations) == (1.5, 0.001, 0.999, 25)
    with pytest.raises(ValueError, match="forward_start"):
        LogBarrierConfig(forward_start="nope")


def test_log_barrier_runs_and_logs_the_cut_test(ideal_nominal_cached):
    result = ioc_bench.run_case("log-barrier", "nominal", "ideal", seed=0, config={"n_random": 3, "max_iterations": 4})
    assert result.status in ("converged", "max_iterations", "infeasible")
    # one projection of the observation (the forward solves' start), 3 random samples, a solve per iteration
    assert 1 <= len(result.history) <= 4 and result.n_solves == 1 + 3 + len(result.history)
    assert all("cost_gap" in h["extra"] for h in result.history)
    assert result.weights == pytest.approx(result.history[result.chosen_iteration]["weights"])
    assert all(w >= 0.001 - 1e-9 for w in result.weights)


@pytest.mark.parametrize("weights", ["nominal", "penalize-dtau", "3,1,5"])
def test_analytic_center_recovers_weights_in_the_ideal_condition(weights):
    result = ioc_bench.run_case("analytic-center", weights, "ideal", seed=0)
    # near the truth the cuts become inconsistent at the reference's own accuracy (~1e-5 of
    # cost): then the relaxed centre is the output
    assert result.status in ("converged", "infeasible")
    assert result.weight_error < 0.01, (result.weights, result.true_weights)
    assert result.trajectory_error < 1e-3
    assert np.isclose(np.linalg.norm(result.weights), 1.0)


def test_bilevels_sparsity_path_is_for_features_that_are_no_effort():
    """The L1 path (distractors may be zero) runs when a non-effort feature is weighed; the
    ankle's effort is an effort, as the walker's are."""
    from types import SimpleNamespace

    from ioc_bench.ioc.bilevel import _has_distractors

    assert not _has_distractors(SimpleNamespace(features=("hip", "knee", "dtau", "ankle")))
    assert _has_distractors(SimpleNamespace(features=("hip", "knee", "dtau", "torso")))
    assert _has_distractors(SimpleNamespace(features=("hip", "knee", "dtau", "work")))
