"""Multi-start: repeatable for a fixed seed, reports its spread, accepts extra guesses."""

from __future__ import annotations

import numpy as np

from ioc_bench import optimize_gait


def test_same_seed_same_optimum_regardless_of_workers():
    a = optimize_gait("penalize-knee", starts=4, seed=3, workers=2)
    b = optimize_gait("penalize-knee", starts=4, seed=3, workers=1)
    assert a.multistart.best == b.multistart.best
    np.testing.assert_array_equal(a.trajectory.q, b.trajectory.q)
    assert [s.report.objective for s in a.multistart.starts] == [s.report.objective for s in b.multistart.starts]


def test_spread_is_reported_and_guesses_are_used(nominal_demo):
    demo = optimize_gait("nominal", starts=3, seed=0, guesses=[nominal_demo], workers=2)
    ms = demo.multistart
    assert len(ms.starts) == 4 and ms.starts[-1].origin.startswith("guess 0")
    assert ms.optima == sorted(ms.optima) and len(ms.optima) >= 1
    assert demo.solver.objective == min(s.report.objective for s in ms.feasible)
    assert "distinct optima" in ms.describe()
