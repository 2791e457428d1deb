"""Single-level's starts on kinematics-only data: bilevel's fit ranked with the others."""

from __future__ import annotations

import numpy as np
import pytest

from ioc_bench import IOCProblem
from ioc_bench.ioc import single_level
from ioc_bench.ioc.bilevel import refine
from ioc_bench.ioc.single_level import SingleLevelConfig
from ioc_bench.synthetic.observe import observe

FEATURES = ("hip", "knee", "dtau")


def _problem(demo, torques: bool, noise: float = 0.05) -> IOCProblem:
    observed = observe(demo.trajectory, noise, np.random.default_rng(0), torques=torques)
    return IOCProblem(observed, FEATURES, demo.params, demo.task)


@pytest.mark.parametrize("torques", [False, True])
def test_bilevels_fit_is_a_start_only_without_torques(penalize_knee_cached, monkeypatch, torques):
    """Without torques the best start's weights are handed to bilevel's fit once (its optimum
    is ranked with the starts); with torques the projection holds the basin and it is not."""
    calls = []
    monkeypatch.setattr(single_level, "refine", lambda problem, w0: calls.append(np.array(w0)))
    problem = _problem(penalize_knee_cached, torques)
    ranked = single_level._starts(problem, SingleLevelConfig(), [])
    assert len(calls) == (0 if torques else 1)
    if calls:
        assert np.allclose(calls[0][0], ranked[0][0])  # the ranked starts, best first (the spy adds none)


def test_bilevel_start_can_be_switched_off(penalize_knee_cached, monkeypatch):
    calls = []
    monkeypatch.setattr(single_level, "refine", lambda problem, w0: calls.append(w0))
    single_level._starts(_problem(penalize_knee_cached, torques=False), SingleLevelConfig(bilevel_start=False), [])
    assert calls == []


def test_refine_fits_an_exact_observation_from_the_uniform_weights(penalize_knee_cached):
    """Bilevel's Gauss-Newton from given weights alone reaches the truth on exact data."""
    demo = penalize_knee_cached
    problem = _problem(demo, torques=True, noise=0.0)
    truth = np.array([demo.weights[f] for f in FEATURES])
    fitted = refine(problem, [np.ones(3) / np.sqrt(3)])
    assert fitted is not None and fitted.status == "converged", fitted
    assert np.mean(np.abs(fitted.weights - truth / np.linalg.norm(truth))) < 1e-3
    assert all(s.success for s in fitted.solutions) and fitted.history


@pytest.mark.parametrize("bad", [1, "yes", None])
def test_a_bilevel_start_that_is_not_a_flag_is_refused(bad):
    with pytest.raises(ValueError, match="bilevel_start must be true or false"):
        SingleLevelConfig(bilevel_start=bad)
