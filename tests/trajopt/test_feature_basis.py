"""A forward problem's feature basis: exposed, validated, and part of every key that shares a
built problem (no solve here: the solvers are replaced where a call would reach them)."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest

from ioc_bench import continuation, optimize
from ioc_bench.demo import Demonstration
from ioc_bench.features import ALL_FEATURES, COST_FEATURES
from ioc_bench.model.params import WalkerParams
from ioc_bench.model.walker import WALKER
from ioc_bench.task import Task
from ioc_bench.trajopt import multistart
from ioc_bench.trajopt.forward_problem import ForwardProblem, basis_key, get_forward_problem
from ioc_bench.trajopt.solution import SolverReport

RICH = (*COST_FEATURES, "work", "collision")
#: Few intervals: the problems build in about a second.
N = 4


class Reached(Exception):
    """Raised by a stand-in where the real call would build or solve."""


def test_forward_problem_exposes_its_basis():
    forward = ForwardProblem(WALKER, N, features=list(RICH))
    assert forward.features == RICH and forward.basis == RICH
    assert forward.step.params.blocks["weights"][1] == (len(RICH),)
    default = ForwardProblem(WALKER, N)
    assert default.features == ALL_FEATURES and default.basis is None  # the default is unchanged


@pytest.mark.parametrize(
    ("features", "message"),
    [
        (("hip", "bogus"), "unknown feature"),
        (("hip", "ankle"), "model 'walker' has no feature"),
        ("hip", "sequence of feature names"),
        (5, "sequence of feature names, got int"),
        ({"hip", "knee"}, "sequence of feature names, got set"),
        ((), "at least one feature"),
    ],
)
def test_a_bad_basis_is_refused_before_building(features, message):
    with pytest.raises(ValueError, match=message):
        ForwardProblem(WALKER, N, features=features)
    with pytest.raises(ValueError, match=message):
        get_forward_problem(WALKER, N, features)


def test_bases_have_their_own_cache_keys():
    assert basis_key(WALKER, None) is None
    assert basis_key(WALKER, list(ALL_FEATURES)) is None  # the default named in full is the default
    assert basis_key(WALKER, RICH) == RICH
    assert basis_key(WALKER, COST_FEATURES) == COST_FEATURES
    assert len({basis_key(WALKER, b) for b in (None, RICH, COST_FEATURES, RICH[::-1])}) == 4
    rich = get_forward_problem(WALKER, N, list(RICH))
    assert rich is get_forward_problem(WALKER, N, RICH)
    assert rich is not get_forward_problem(WALKER, N)
    assert get_forward_problem(WALKER, N) is get_forward_problem(WALKER, N, ALL_FEATURES)
    assert get_forward_problem(WALKER, N).features == ALL_FEATURES and rich.features == RICH


@pytest.mark.parametrize(("features", "key"), [(RICH, RICH), (ALL_FEATURES, None)])
def test_multistart_jobs_carry_the_basis(monkeypatch, features, key):
    seen = []

    def fake(model, n_intervals, basis=None):
        seen.append((model.name, n_intervals, basis))
        return SimpleNamespace(solve=lambda request: "solved")

    monkeypatch.setattr(multistart, "get_forward_problem", fake)
    forward = SimpleNamespace(model=WALKER, n_intervals=N, basis=basis_key(WALKER, features))
    assert multistart.solve_starts(forward, ["request"], workers=1) == ["solved"]
    assert seen == [("walker", N, key)]


def test_optimize_gait_takes_a_basis(monkeypatch):
    seen = []

    def fake(model, n_intervals, basis=None):
        seen.append(basis)
        raise Reached

    monkeypatch.setattr(optimize, "get_forward_problem", fake)
    with pytest.raises(Reached):
        optimize.optimize_gait([1, 2, 3, 4, 5], starts=1, workers=1, features=RICH)
    with pytest.raises(Reached):
        optimize.optimize_gait("nominal", starts=1, workers=1, features=RICH)  # over the cost features, others 0
    with pytest.raises(Reached):
        optimize.optimize_gait("nominal", starts=1, workers=1)
    assert seen == [RICH, RICH, None]
    with pytest.raises(ValueError, match="expected 3 weights"):
        optimize.optimize_gait([1, 2, 3, 4], starts=1, workers=1, features=RICH)
    with pytest.raises(ValueError, match="unknown feature"):
        optimize.optimize_gait("nominal", starts=1, workers=1, features=("hip", "bogus"))
    assert len(seen) == 3  # refused before the forward problem


def test_solve_step_passes_the_basis(monkeypatch):
    from ioc_bench.human import load_step, scoring

    seen = []

    def fake(*args, **kwargs):
        seen.append(kwargs.get("features"))
        raise Reached

    monkeypatch.setattr(scoring, "optimize_gait", fake)
    step = load_step("WBDS01", "T05")
    for features in (RICH, None):
        with pytest.raises(Reached):
            scoring.solve_step(np.ones(5), step, 1, 0, task=Task(step.task.speed), features=features)
    assert seen == [RICH, None]


def _demo(weights: dict[str, float], task: Task) -> Demonstration:
    report = SolverReport("Solve_Succeeded", True, 0.0, 0.0, 1, 0.1, 1.0)
    return Demonstration(None, weights, {}, WalkerParams(), task, report, n_intervals=N)


@pytest.mark.parametrize(
    ("weights", "key"),
    [
        (dict(zip(RICH, (0.5, 0.5, 0.5, 0.5, 0.0))), RICH),
        (dict.fromkeys(ALL_FEATURES, 0.5), None),
        ({"hip": 1.0}, None),  # a loaded demonstration may name fewer of the default features
    ],
)
def test_continuation_keeps_a_basis(monkeypatch, weights, key):
    seen = []

    def fake(w, params, task, **kwargs):
        seen.append(kwargs["features"])
        return _demo(w, task)

    monkeypatch.setattr(continuation, "optimize_gait", fake)
    end = continuation.continue_gait(_demo(weights, Task(0.27)), Task(0.3), verify=False)
    assert end.success and seen and set(seen) == {key}
