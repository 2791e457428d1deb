"""Robustness curves and their area, on made-up results."""

from __future__ import annotations

import numpy as np
import pytest

from ioc_bench.synthetic.case import CaseResult
from ioc_bench.synthetic.conditions import AXES, axis_conditions
from ioc_bench.synthetic.robustness import auc_table, curves
from ioc_bench.synthetic.suites import get_suite


def _result(condition: str, error: float, weight_set: str = "nominal") -> CaseResult:
    w = (0.577, 0.577, 0.577)
    return CaseResult(
        algorithm="alg", weight_set=weight_set, condition=condition, seed=0, features=("hip", "knee", "dtau"),
        status="converged", reason="", weights=w, true_weights=w, weight_error=error, trajectory_error=0.0,
        n_solves=1, wall_time=1.0,
    )  # fmt: skip


def test_robustness_suite_covers_every_axis_once():
    suite = get_suite("robustness")
    for axis in AXES:
        names = [c.name for c in axis_conditions(axis)]
        assert set(names) <= set(suite.conditions) and names[0 if axis == "noise" else 2] == "ideal"
    assert len(suite.conditions) == len(set(suite.conditions)) == 13


def test_auc_is_the_mean_error_over_the_severity_range():
    results = []
    for axis in AXES:
        for c in axis_conditions(axis):
            # error grows linearly with |severity|: mean over the range is half the largest error
            results += [_result(c.name, abs(c.severity) / 100, ws) for ws in ("nominal", "penalize-hip")]
    table = auc_table(results)
    assert table["alg"]["noise"] == pytest.approx(0.05)  # 0..10 %: mean of 0..0.1
    assert table["alg"]["mass"] == pytest.approx(0.1) and table["alg"]["speed"] == pytest.approx(0.1)
    assert table["alg"]["mean"] == pytest.approx((0.05 + 0.1 + 0.1) / 3)
    noise = next(c for c in curves(results) if c.axis == "noise")
    assert np.all(noise.low <= noise.mean + 1e-12) and np.all(noise.mean <= noise.high + 1e-12)


def test_an_incomplete_axis_has_no_auc():
    results = [_result("ideal", 0.0), _result("noise-1", 0.01), _result("noise-2", 0.02)]
    assert auc_table(results) == {}
    assert len(curves(results)) == 1  # the curve is still drawn
    assert curves(results[:2]) == []  # two points are a condition, not a curve
