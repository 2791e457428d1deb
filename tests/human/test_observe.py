"""The observation of a human step holds only what was measured."""

from __future__ import annotations

import numpy as np
import pytest

from ioc_bench.human import LEG_SEGMENTS, human_observation, load_step, measured_mask, segment_rmse_deg
from ioc_bench.human.observe import TORSO_GUESS, leg_angles, walker_ground_force
from ioc_bench.model.walker import ACTUATORS, SEGMENTS, walker_linkage
from ioc_bench.trajectory import Observation


@pytest.fixture(scope="module")
def step():
    return load_step("WBDS01", "T04")


def _column_names(torques: bool) -> list[str]:
    names = [f"{kind}:{seg}:{c}" for kind in ("q", "v") for seg in SEGMENTS for c in ("x", "z", "theta")]
    return names + ([f"tau:{a}" for a in ACTUATORS] if torques else [])


@pytest.mark.parametrize("torques", [False, True])
def test_the_mask_hides_exactly_the_unmeasured_signals(step, torques: bool) -> None:
    obs = human_observation(step, torques=torques)
    signals = obs.signals()
    names = _column_names(torques)
    assert signals.shape == (41, len(names))
    measured = {n for n in names if n.endswith(":theta") and n.split(":")[1] in LEG_SEGMENTS}
    measured |= {n for n in names if torques and n.startswith("tau:")}
    visible = {n for n, col in zip(names, signals.T) if np.all(np.isfinite(col))}
    hidden = {n for n, col in zip(names, signals.T) if np.all(np.isnan(col))}
    assert visible == measured
    assert hidden == set(names) - measured
    assert np.array_equal(obs.measured, measured_mask(torques))


def test_measured_columns_are_the_steps_numbers(step) -> None:
    obs = human_observation(step, torques=True)
    legs = [SEGMENTS.index(n) for n in LEG_SEGMENTS]
    np.testing.assert_array_equal(obs.q[:, legs, 2], step.angles)
    np.testing.assert_array_equal(obs.v[:, legs, 2], step.rates)
    np.testing.assert_array_equal(obs.tau, step.torques)
    assert human_observation(step).tau is None
    assert obs.dt == step.dt


def test_the_unmeasured_guess_is_a_joined_linkage(step) -> None:
    obs = human_observation(step)
    linkage = walker_linkage(step.params)
    assert np.all(obs.q[:, SEGMENTS.index("torso"), 2] == TORSO_GUESS)
    foot = obs.point(linkage, "shank_stance", "foot")
    np.testing.assert_allclose(foot, 0.0, atol=1e-12)
    hip_a, hip_b = obs.point(linkage, "thigh_stance", "hip"), obs.point(linkage, "thigh_swing", "hip")
    np.testing.assert_allclose(hip_a, hip_b, atol=1e-12)
    # Position rates agree with central differences of the positions along finely spaced knots.
    fine = human_observation(load_step("WBDS01", "T04", n_intervals=200))
    central = (fine.q[2:, :, :2] - fine.q[:-2, :, :2]) / (2 * fine.dt)
    np.testing.assert_allclose(fine.v[1:-1, :, :2], central, atol=1e-3 * np.abs(fine.v[:, :, :2]).max())


def test_with_signals_keeps_the_guess_where_unmeasured(step) -> None:
    obs = human_observation(step)
    again = obs.with_signals(obs.signals())
    np.testing.assert_array_equal(again.q, obs.q)
    np.testing.assert_array_equal(again.v, obs.v)


def test_segment_rmse(step) -> None:
    obs = human_observation(step)
    assert segment_rmse_deg(obs, step) == 0.0
    shifted = Observation(obs.dt, obs.q.copy(), obs.v, None)
    legs = [SEGMENTS.index(n) for n in LEG_SEGMENTS]
    shifted.q[:, legs[0], 2] += np.radians(4.0)  # one of four segments off by 4 deg: RMSE 2 deg
    assert segment_rmse_deg(shifted, step) == pytest.approx(2.0)
    assert segment_rmse_deg(shifted, obs) == pytest.approx(2.0)
    np.testing.assert_array_equal(leg_angles(obs), step.angles)
    short = load_step("WBDS01", "T04", n_intervals=10)
    with pytest.raises(ValueError, match="cannot compare a step of 41 knots with one of 21"):
        segment_rmse_deg(obs, short)


def test_walker_ground_force_reads_the_ground_pin(nominal_demo) -> None:
    force = walker_ground_force(nominal_demo.trajectory)
    assert force.shape == (nominal_demo.trajectory.n_knots, 2)
    # The walker's weight is 1: over its single support the vertical force averages about 1
    # (less by what the heel-strike impulse carries).
    assert 0.7 < force[:, 1].mean() < 1.1
