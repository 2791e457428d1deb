"""Model-free baselines of the human track: known answers on hand-made steps, and the shipped data."""

from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import pytest

from ioc_bench.human import load_step
from ioc_bench.human.baselines import (
    cadence,
    change_r2,
    interpolate,
    log_error,
    pooled_change_r2,
    population_change,
    power_law_exponent,
    power_law_step_length,
)
from ioc_bench.human.scoring import rmse_deg

SUBJECTS = ("WBDS01", "WBDS02", "WBDS03")
CODES = ("T03", "T04", "T05", "T06")


def _step(speed: float, step_length: float = 0.7, angles: np.ndarray | None = None) -> SimpleNamespace:
    """A stand-in for a HumanStep: angles and task only."""
    if angles is None:
        angles = np.full((41, 4), speed)
    return SimpleNamespace(angles=angles, task=SimpleNamespace(speed=speed, step_length=step_length))


def _change(seed: int, scale: float = 1.0) -> np.ndarray:
    return scale * np.random.default_rng(seed).normal(size=(41, 4))


@pytest.fixture(scope="module")
def shipped() -> dict[tuple[str, str], object]:
    return {(s, c): load_step(s, c) for s in SUBJECTS for c in CODES}


# population_change


def test_population_change_is_the_mean_change_of_the_pairs():
    a, b = _change(1), _change(2)
    pairs = [
        (_step(0.3, angles=np.zeros((41, 4))), _step(0.4, angles=a)),
        (_step(0.3, angles=b), _step(0.4, angles=3 * b)),
    ]
    np.testing.assert_allclose(population_change(pairs), 0.5 * (a + 2 * b))


def test_population_change_without_pairs_is_none():
    assert population_change([]) is None


def test_population_change_beats_copy_on_shipped_data(shipped):
    # Checked by hand: WBDS01 T03 -> T05, population 2.39 deg vs copy 2.86 deg.
    train, target = shipped["WBDS01", "T03"], shipped["WBDS01", "T05"]
    change = population_change([(shipped[s, "T03"], shipped[s, "T05"]) for s in ("WBDS02", "WBDS03")])
    assert change.shape == (41, 4)
    assert rmse_deg(train.angles + change, target.angles) < rmse_deg(train.angles, target.angles)


# interpolate


def test_interpolate_halfway_is_the_mean_of_the_two_steps():
    lo, hi = _step(0.3, 0.6, _change(1)), _step(0.5, 0.8, _change(2))
    far = _step(0.9, 2.0, _change(3))
    got = interpolate([far, hi, lo], 0.4)
    np.testing.assert_allclose(got.angles, 0.5 * (lo.angles + hi.angles))
    assert got.step_length == pytest.approx(0.7)


def test_interpolate_uses_the_nearest_steps_and_is_linear():
    steps = [_step(v, 2 * v) for v in (0.2, 0.3, 0.5, 0.6)]
    got = interpolate(steps, 0.35)
    np.testing.assert_allclose(got.angles, 0.35)
    assert got.step_length == pytest.approx(0.7)


@pytest.mark.parametrize("target", [0.1, 0.2, 0.3, 0.6, 0.7])
def test_interpolate_needs_a_strict_bracket(target):
    # outside the training speeds, or exactly at one of them (bound or inner): no prediction
    steps = [_step(v) for v in (0.2, 0.3, 0.6)]
    assert interpolate(steps, target) is None


def test_interpolate_with_one_step_is_none():
    assert interpolate([_step(0.3)], 0.4) is None


# power law


def test_power_law_exponent_recovers_an_exact_law():
    steps = [_step(v, 1.3 * v**0.4) for v in (0.2, 0.25, 0.3, 0.4, 0.5)]
    assert power_law_exponent(steps) == pytest.approx(0.4)


def test_power_law_exponent_needs_two_distinct_speeds():
    with pytest.raises(ValueError, match="2 distinct speeds"):
        power_law_exponent([_step(0.3, 0.6), _step(0.3, 0.7)])
    with pytest.raises(ValueError):
        power_law_exponent([])


def test_power_law_exponent_of_shipped_steps_is_plausible(shipped):
    b = power_law_exponent(list(shipped.values()))
    print(f"pooled exponent over {len(shipped)} shipped steps: {b:.4f}")
    assert 0.2 < b < 0.8


def test_power_law_step_length_scales_the_training_step():
    train = _step(0.3, 0.6)
    assert power_law_step_length(train, 0.6, 0.5) == pytest.approx(0.6 * math.sqrt(2))
    assert power_law_step_length(train, 0.3, 0.4) == pytest.approx(0.6)


# errors


def test_log_error_is_symmetric_and_nan_on_failure():
    assert log_error(2.0, 1.0) == pytest.approx(math.log(2))
    assert log_error(1.0, 2.0) == pytest.approx(math.log(2))
    assert log_error(0.7, 0.7) == 0.0
    for bad in (float("nan"), float("inf"), 0.0, -1.0):
        assert math.isnan(log_error(bad, 1.0))
        assert math.isnan(log_error(1.0, bad))


def test_change_r2_known_answers():
    person = _change(4)
    assert change_r2(person, person) == 1.0
    assert change_r2(np.zeros_like(person), person) == 0.0
    assert change_r2(2 * person, person) == pytest.approx(0.0)
    assert change_r2(-person, person) == pytest.approx(-3.0)


def test_change_r2_is_nan_for_failures_and_no_change():
    person = _change(4)
    assert math.isnan(change_r2(None, person))
    bad = person.copy()
    bad[3, 1] = np.nan
    assert math.isnan(change_r2(bad, person))
    assert math.isnan(change_r2(person, np.zeros_like(person)))


def test_pooled_change_r2_weighs_pairs_by_their_change():
    small, large = _change(5, 0.1), _change(6, 3.0)
    pred_small, pred_large = small + _change(7, 0.05), 0.5 * large
    error = np.sum((pred_small - small) ** 2) + np.sum((pred_large - large) ** 2)
    total = np.sum(small**2) + np.sum(large**2)
    got = pooled_change_r2([(pred_small, small), (pred_large, large)])
    assert got == pytest.approx(1 - error / total)
    assert got != pytest.approx(0.5 * (change_r2(pred_small, small) + change_r2(pred_large, large)))


def test_pooled_change_r2_skips_failures_and_copy_is_zero():
    a, b = _change(8), _change(9, 2.0)
    bad = np.full_like(a, np.inf)
    assert pooled_change_r2([(a, a), (None, b), (bad, b)]) == 1.0
    assert pooled_change_r2([(np.zeros_like(a), a), (np.zeros_like(b), b)]) == 0.0
    assert math.isnan(pooled_change_r2([(None, a), (bad, b)]))
    assert math.isnan(pooled_change_r2([]))


def test_cadence_log_error_equals_step_lengths_at_fixed_speed():
    assert cadence(0.5, 0.4) == pytest.approx(0.8)
    speed, predicted, measured = 0.4, 0.62, 0.7
    assert log_error(cadence(predicted, speed), cadence(measured, speed)) == pytest.approx(
        log_error(predicted, measured)
    )
