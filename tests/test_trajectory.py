"""Observations that measure only part of a step (the measurement mask)."""

import numpy as np
import pytest

from ioc_bench.trajectory import Observation
from ioc_bench.trajopt.tracking import signal_spans, tracking_error


def _step(knots: int = 5, segments: int = 2, actuators: int = 1) -> Observation:
    rng = np.random.default_rng(0)
    q = rng.normal(size=(knots, segments, 3))
    v = rng.normal(size=(knots, segments, 3))
    return Observation(0.1, q, v, rng.normal(size=(knots, actuators)))


def test_unmeasured_signals_are_nan_but_their_values_stay_as_a_guess():
    full = _step()
    mask = np.zeros(13, dtype=bool)
    mask[[2, 5]] = True  # the two segments' angles only
    part = Observation(full.dt, full.q, full.v, full.tau, mask)
    sig = part.signals()
    assert np.isfinite(sig[:, mask]).all() and np.isnan(sig[:, ~mask]).all()
    assert np.array_equal(part.q, full.q)  # the estimate is kept for a solver's guess
    noisy = part.with_signals(sig + 1.0)
    assert np.allclose(noisy.q[:, :, 2], full.q[:, :, 2] + 1.0)
    assert np.array_equal(noisy.q[:, :, :2], full.q[:, :, :2]) and noisy.measured is part.measured


def test_metrics_skip_unmeasured_signals():
    full = _step()
    mask = np.zeros(13, dtype=bool)
    mask[2] = True
    part = Observation(full.dt, full.q, full.v, full.tau, mask)
    other = Observation(full.dt, full.q + np.array([5.0, 5.0, 0.0]), full.v, full.tau)  # positions off, angles same
    spans = signal_spans(part)
    assert tracking_error(other, part, spans) == 0.0
    assert spans[~mask].tolist() == [1.0] * 12


@pytest.mark.parametrize("mask", [np.ones(12, dtype=bool), np.ones(13), np.zeros(13, dtype=bool)])
def test_a_bad_mask_is_refused(mask):
    full = _step()
    with pytest.raises(ValueError, match="measured"):
        Observation(full.dt, full.q, full.v, full.tau, mask)
