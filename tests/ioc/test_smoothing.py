"""The noise estimate behind the smoothed reference of a noisy observation."""

import numpy as np
import pytest

from ioc_bench.ioc.smoothing import NOISE_FLOOR, discrepancy_target, noise_level


def _signals(noise: float, seed: int = 0) -> np.ndarray:
    t = np.linspace(0, 1, 41)[:, None]
    phases = np.linspace(0, 3, 30)[None, :]
    smooth = np.sin(2 * np.pi * t + phases) + 0.3 * np.cos(4 * np.pi * t * (1 + phases / 3))
    span = smooth.max(axis=0) - smooth.min(axis=0)
    return smooth + np.random.default_rng(seed).normal(size=smooth.shape) * noise * span


@pytest.mark.parametrize("noise", [0.01, 0.05, 0.1])
def test_noise_level_recovers_the_noise_of_smooth_signals(noise):
    assert noise_level(_signals(noise)) == pytest.approx(noise, rel=0.25)


def test_an_exact_step_reads_below_the_floor_and_unmeasured_columns_are_left_out():
    sig = _signals(0.0)
    assert noise_level(sig) < NOISE_FLOOR
    sig[:, :5] = np.nan
    assert noise_level(sig) < NOISE_FLOOR
    assert noise_level(np.full((41, 3), np.nan)) == 0.0


def test_the_discrepancy_target_lies_between_the_plain_fit_and_the_noise():
    assert discrepancy_target(0.002, 0.05) == pytest.approx(0.002 + 0.5 * (0.0025 - 0.002))
    assert discrepancy_target(0.003, 0.05) == 0.003  # already past the noise: no smoothing allowed
