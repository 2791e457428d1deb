"""The weight optimization on synthetic cuts with a known answer."""

from __future__ import annotations

import numpy as np

from ioc_bench.ioc.weight_fit import fit_weights, max_margin


def _cuts(true: np.ndarray, n: int, rng: np.random.Generator, scale: float = 1e-5) -> np.ndarray:
    """Random feature differences that every true-weight-optimal observation satisfies."""
    d = rng.normal(size=(n, true.size)) * scale
    return np.where((d @ true)[:, None] < 0, -d, d)


def test_paper_objective_separates_tiny_raw_differences(rng):
    """Raw differences ~1e-5 must still be separated (rows are scaled for the constraint)."""
    true = np.array([1.0, 1.0, 1.0]) / np.sqrt(3)
    d = _cuts(true, 30, rng)
    fit = fit_weights(d, "paper")
    assert fit.success
    assert np.all(d @ fit.weights >= -1e-12)
    assert np.isclose(np.linalg.norm(fit.weights), 1.0)
    assert np.all((fit.weights >= 0.001 - 1e-9) & (fit.weights <= 0.999 + 1e-9))


def test_center_converges_to_truth_as_cuts_accumulate(rng):
    true = np.array([10.0, 1.0, 1.0]) / np.sqrt(102)
    errors = []
    for n in (5, 50, 500):
        fit = fit_weights(_cuts(true, n, rng), "center", lower=0.0, upper=1.0)
        assert fit.success
        errors.append(np.abs(fit.weights - true).mean())
    assert errors[-1] < errors[0] and errors[-1] < 0.02


def test_inconsistent_cuts_are_infeasible_until_relaxed_by_the_max_margin():
    # w1 >= 2 w2 and w2 >= 2 w1 force w1 = w2 = 0, and then w3 <= 0: no unit weights fit.
    d = np.array([[1.0, -2.0, 0.0], [-2.0, 1.0, 0.0], [0.0, 0.0, -1.0]])
    assert not fit_weights(d, "center", lower=0.0, upper=1.0).success
    assert not fit_weights(d, "paper").success
    t = max_margin(d)
    assert t < 0
    relaxed = fit_weights(d, "center", lower=0.0, upper=1.0, relax=1.5 * -t)
    assert relaxed.success and relaxed.min_margin >= 1.5 * t - 1e-8
    assert not fit_weights(d, "center", lower=0.0, upper=1.0, relax=0.5 * -t).success
