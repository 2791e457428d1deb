"""The misfit test: a model that can produce the observation passes it, a wrong one does not."""

from __future__ import annotations

import numpy as np
import pytest

from ioc_bench import IOCProblem
from ioc_bench.ioc.misfit import THRESHOLD, gauss_newton_region, residual_test
from ioc_bench.synthetic.observe import observe
from ioc_bench.synthetic.results import parse_result

FEATURES = ("hip", "knee", "dtau")


def _problem(demo, noise: float, params=None) -> IOCProblem:
    observed = observe(demo.trajectory, noise, np.random.default_rng([0, 7]))
    return IOCProblem(observed, FEATURES, params or demo.params, demo.task)


def _true_weights(demo) -> np.ndarray:
    w = np.array([demo.weights[f] for f in FEATURES])
    return w / np.linalg.norm(w)


def test_the_true_step_fits_a_noisy_observation_and_another_optimum_does_not(penalize_knee_cached):
    demo = penalize_knee_cached
    problem = _problem(demo, 0.05)
    truth = residual_test([problem], [demo.trajectory], len(FEATURES))
    assert not truth.rejected and 0.7 < truth.statistic < 1.3, truth  # the noise's own size
    assert truth.noise_level == pytest.approx(0.05, rel=0.15)
    other = problem.optimize(np.ones(3), start=demo.trajectory)  # optimal, but for other weights
    assert other.success
    fit = residual_test([problem], [other], len(FEATURES))
    assert fit.rejected and fit.statistic > THRESHOLD, fit


def test_a_wrong_model_is_rejected_on_exact_data(penalize_knee_cached):
    demo = penalize_knee_cached
    exact = _problem(demo, 0.0)
    own = residual_test([exact], [demo.trajectory], len(FEATURES))
    assert not own.rejected and own.statistic < 1e-3, own
    heavy = _problem(demo, 0.0, demo.params.with_leg_mass_scale(1.1))  # the mass condition's belief
    sol = heavy.optimize(_true_weights(demo), start=demo.trajectory)
    assert sol.success
    wrong = residual_test([heavy], [sol], len(FEATURES))
    assert wrong.rejected and wrong.statistic > 100 * THRESHOLD, wrong


def test_the_gauss_newton_region_holds_a_linear_fit_and_narrows_with_less_noise():
    rng = np.random.default_rng(3)
    w = np.array([0.6, 0.8])
    jacobian = rng.normal(size=(400, 2))
    wide = gauss_newton_region(0.1 * rng.normal(size=400), jacobian, w, "test")
    narrow = gauss_newton_region(0.01 * rng.normal(size=400), jacobian, w, "test")
    assert wide.contains(w) and narrow.contains(w)
    assert narrow.width < wide.width
    assert np.allclose(np.asarray(wide.covariance) @ w, 0.0, atol=1e-12)  # no spread along w: |w| = 1


def test_a_result_file_with_a_malformed_model_fit_is_refused(make_result):
    good = make_result().to_dict()
    fit = {"rejected": True, "statistic": 40.0, "threshold": 2.0, "noise_level": 1e-4, "tracking_error": 4e-7}
    fit["method"] = "test"
    assert parse_result(good | {"model_fit": fit}).misfit is True
    assert parse_result(good).misfit is None
    for bad, message in (
        (fit | {"statistic": -1.0}, "model_fit.statistic"),
        (fit | {"rejected": "yes"}, "model_fit.rejected"),
        ({k: v for k, v in fit.items() if k != "threshold"}, "model_fit must have the fields"),
    ):
        with pytest.raises(ValueError, match=message):
            parse_result(good | {"model_fit": bad})
