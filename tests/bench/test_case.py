"""``run_case`` records an algorithm's faults as failed results, and scores good answers."""

from __future__ import annotations

import numpy as np
import pytest

import ioc_bench
from ioc_bench.ioc import registry
from ioc_bench.ioc.algorithm import IOCAlgorithm, IOCResult
from ioc_bench.provenance import provenance
from ioc_bench.synthetic.results import parse_result


@pytest.fixture
def register(monkeypatch):
    monkeypatch.setattr(registry, "_REGISTRY", dict(registry._REGISTRY))

    def add(name, fit):
        cls = type(name, (IOCAlgorithm,), {"fit": fit, "description": name})
        ioc_bench.register_algorithm(name)(cls)
        return name

    return add


def _raises(self, problem):
    raise RuntimeError("boom")


@pytest.mark.parametrize(
    ("fit", "reason"),
    [
        (_raises, "RuntimeError: boom"),
        (lambda self, p: IOCResult(np.ones(p.n_features + 1)), "returned 4 weights for 3 features"),
        (lambda self, p: IOCResult(np.array([np.nan, 1.0, 1.0])), "non-finite"),
        (lambda self, p: IOCResult(np.array([-1.0, 1.0, 1.0])), "negative"),
        (lambda self, p: IOCResult(np.zeros(3)), "all-zero"),
        (lambda self, p: [1, 2, 3], "not IOCResult"),
    ],
)
def test_misbehaving_algorithm_gives_failed_result(register, fit, reason, ideal_nominal_cached):
    name = register(f"bad-{abs(hash(reason))}", fit)
    result = ioc_bench.run_case(name, "nominal", "ideal", seed=0)
    assert result.status == "failed"
    assert reason in result.reason
    assert np.isnan(result.weight_error)
    assert result.provenance == provenance()  # a failed case says what it ran with too


def test_oracle_counts_and_perfect_answer_scores_zero(register, ideal_nominal_cached):
    def fit(self, problem):
        problem.optimize(np.ones(3))  # starts at the projected observation: one projection, one solve
        assert not hasattr(problem, "weights") and not hasattr(problem.observed, "weights")
        hidden = ("acc", "pin_forces", "lock", "impulses", "trail_impulse", "lock_impulses")
        assert not any(hasattr(problem.observed, name) for name in hidden)  # only what a lab measures
        return IOCResult(np.ones(3))  # the truth for the nominal set

    name = register("oracle-user", fit)
    result = ioc_bench.run_case(name, "nominal", "ideal", seed=0)
    assert result.status == "converged"
    assert result.oracle["calls"]["optimize"] == 1 and result.oracle["calls"]["project"] == 1
    assert result.n_solves == 2
    assert result.weight_error == pytest.approx(0.0, abs=1e-12)
    assert result.trajectory_error < 1e-6  # the truth regenerates the observed step


def test_result_round_trips_through_json(register, ideal_nominal_cached):
    import json

    name = register("fixed-json", lambda self, p: IOCResult(np.array([1.0, 2.0, 3.0])))
    result = ioc_bench.run_case(name, "nominal", "ideal", seed=0)
    again = parse_result(json.loads(json.dumps(result.to_dict())))
    assert again == result
    assert result.provenance == provenance() and result.provenance["commit"]  # recorded when the case ran


def test_a_stored_reference_is_the_same_and_counts_its_projections(nominal_demo, tmp_path, monkeypatch):
    from ioc_bench.features import COST_FEATURES
    from ioc_bench.ioc.problem import IOCProblem
    from ioc_bench.synthetic.demos import ReferenceCache
    from ioc_bench.synthetic.observe import observe
    from ioc_bench.trajopt.forward_problem import ForwardProblem

    observed = observe(nominal_demo.trajectory, 0.05, np.random.default_rng(3))
    store = ReferenceCache(tmp_path)

    def problem():
        return IOCProblem(observed, COST_FEATURES, nominal_demo.params, nominal_demo.task, reference_store=store)

    first = problem()
    made = first.reference()
    assert made.success and first.stats.calls["project"] >= 2  # noisy: projected, then smoothed

    def forbidden(*args, **kwargs):
        raise AssertionError("the stored reference was solved again")

    monkeypatch.setattr(ForwardProblem, "solve", forbidden)
    second = problem()
    again = second.reference()
    assert np.array_equal(again.point.x, made.point.x) and np.array_equal(again.features, made.features)
    assert second.stats.calls["project"] == first.stats.calls["project"]
    # ... and its seconds, so a case that reuses it is timed as if it had projected itself.
    assert second.stats.seconds["reused_reference"] >= first.stats.seconds["project"] > 0
