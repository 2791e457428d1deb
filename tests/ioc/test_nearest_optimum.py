"""The weights' optimum in the observed step's basin: a proximal step, then a free solve."""

from __future__ import annotations

import math

import numpy as np
import pytest

from ioc_bench import IOCProblem
from ioc_bench.ioc.bilevel import BilevelConfig
from ioc_bench.ioc.nearest_optimum import nearest_optimum
from ioc_bench.ioc.single_level import SingleLevelConfig
from ioc_bench.synthetic.observe import observe

FEATURES = ("hip", "knee", "dtau")


def _problem(demo, torques: bool) -> IOCProblem:
    observed = observe(demo.trajectory, 0.0, np.random.default_rng(0), torques=torques)
    return IOCProblem(observed, FEATURES, demo.params, demo.task)


def _true_weights(demo) -> np.ndarray:
    w = np.array([demo.weights[f] for f in FEATURES])
    return w / np.linalg.norm(w)


def test_with_torques_observed_it_is_one_straight_solve(penalize_knee_cached):
    problem = _problem(penalize_knee_cached, torques=True)
    start = problem.reference()
    solves = problem.stats.calls["optimize"]
    sol = nearest_optimum(problem, _true_weights(penalize_knee_cached), start, proximal=100.0)
    assert problem.stats.calls["optimize"] == solves + 1
    straight = problem.optimize(_true_weights(penalize_knee_cached), start=start)
    assert np.array_equal(sol.trajectory.q, straight.trajectory.q)


def test_without_torques_it_keeps_the_optimum_nearer_the_observation(penalize_knee_cached):
    """Three solves; the answer is a free optimum of the weights (a solve from it does not
    move), here the demonstrated step, whichever of the straight and the proximal solve
    reached it (at weight 100 on this exact observation the proximal one does not: it ends
    0.17 rad away, at an optimum 5 % costlier)."""
    demo = penalize_knee_cached
    problem = _problem(demo, torques=False)
    w = _true_weights(demo)
    solves = problem.stats.calls["optimize"]
    sol = nearest_optimum(problem, w, problem.reference(), proximal=100.0)
    assert problem.stats.calls["optimize"] == solves + 3
    assert sol.success, sol.status
    again = problem.optimize(w, start=sol)
    assert np.max(np.abs(again.trajectory.q - sol.trajectory.q)) < 1e-6
    assert np.max(np.abs(sol.trajectory.q - demo.trajectory.q)) < 1e-5
    assert problem.tracking_error(sol.trajectory) < 1e-10


def test_proximal_zero_is_the_straight_solve(penalize_knee_cached):
    problem = _problem(penalize_knee_cached, torques=False)
    solves = problem.stats.calls["optimize"]
    nearest_optimum(problem, _true_weights(penalize_knee_cached), problem.reference(), proximal=0.0)
    assert problem.stats.calls["optimize"] == solves + 1


@pytest.mark.parametrize("config", [BilevelConfig, SingleLevelConfig])
@pytest.mark.parametrize("bad", [-1.0, math.inf, math.nan])
def test_a_bad_proximal_weight_is_refused(config, bad):
    with pytest.raises(ValueError, match="proximal must be a finite number >= 0"):
        config(proximal=bad)
