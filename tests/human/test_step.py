"""Mapping a trial to the walker's step: conventions, phases, units, signs."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from ioc_bench.features import PAPER_GRAVITY
from ioc_bench.human import load_step
from ioc_bench.human.step import human_step, pose_step_length
from ioc_bench.human.wbds import CYCLE_ROWS, MeanCycle, WbdsData, WbdsTrial

PHASE = np.linspace(0.0, 1.0, CYCLE_ROWS)
ALL_TRIALS = [(s, t) for s in ("WBDS01", "WBDS02", "WBDS03") for t in ("T03", "T04", "T05", "T06")]


def _with_angles(trial: WbdsTrial, **columns: np.ndarray | float) -> WbdsTrial:
    """``trial`` with some angle columns replaced (scalars broadcast over the stride)."""
    new = dict(trial.angles.columns)
    for name, value in columns.items():
        new[name] = np.broadcast_to(np.asarray(value, dtype=float), (CYCLE_ROWS,)).copy()
    return dataclasses.replace(trial, angles=MeanCycle(trial.angles.path, new))


@pytest.fixture(scope="module")
def trial() -> WbdsTrial:
    return WbdsData().trial("WBDS01", "T05")


def _posture(trial, pelvis, hip, knee, left_offset=0.0):
    return _with_angles(
        trial,
        RPelvisAngleZ=pelvis,
        LPelvisAngleZ=pelvis,
        RHipAngleZ=hip + left_offset,
        LHipAngleZ=hip - left_offset,
        RKneeAngleZ=knee,
        LKneeAngleZ=knee,
    )


def test_a_flexed_hip_puts_the_knee_ahead(trial: WbdsTrial) -> None:
    # Pelvis tilted 10 deg forward, hip flexed 30: the thigh is 20 deg ahead of vertical,
    # its knee in front of the hip, so the walker's thigh angle (proximal end ahead
    # positive) is -20. Knee flexed 20: the shank is vertical.
    step = human_step(_posture(trial, 10.0, 30.0, 20.0))
    np.testing.assert_allclose(np.degrees(step.angles), np.tile([-20.0, 0.0, -20.0, 0.0], (step.n_knots, 1)), atol=1e-9)
    np.testing.assert_allclose(step.rates, 0.0, atol=1e-9)


def test_an_extended_hip_puts_the_knee_behind(trial: WbdsTrial) -> None:
    step = human_step(_posture(trial, 10.0, -10.0, 5.0))
    np.testing.assert_allclose(np.degrees(step.angles[0]), [20.0, 25.0, 20.0, 25.0], atol=1e-9)


def test_both_legs_are_averaged(trial: WbdsTrial) -> None:
    step = human_step(_posture(trial, 10.0, 30.0, 20.0, left_offset=4.0))
    np.testing.assert_allclose(np.degrees(step.angles[:, 0]), -20.0, atol=1e-9)
    assert step.checks.asymmetry_deg == pytest.approx(math.sqrt(0.5 * 8.0**2 + 0.5 * 8.0**2))


def test_stance_and_swing_are_half_a_stride_apart(trial: WbdsTrial) -> None:
    amplitude = 25.0
    hip = amplitude * np.sin(2 * np.pi * PHASE)
    step = human_step(_posture(trial, 0.0, hip, 0.0))
    s = step.fractions
    np.testing.assert_allclose(np.degrees(step.angles[:, 0]), -amplitude * np.sin(np.pi * s), atol=1e-3)
    np.testing.assert_allclose(np.degrees(step.angles[:, 2]), -amplitude * np.sin(np.pi + np.pi * s), atol=1e-3)
    # Rates in rad per walker time unit: d/dt of -A sin(pi s) with s = t / duration.
    expected = -np.radians(amplitude) * np.pi * np.cos(np.pi * s) / step.duration
    np.testing.assert_allclose(step.rates[:, 0], expected, rtol=1e-3, atol=1e-4)


def test_the_step_is_periodic_under_the_leg_swap() -> None:
    step = load_step("WBDS02", "T04")
    np.testing.assert_allclose(step.angles[-1], step.angles[0][[2, 3, 0, 1]], atol=1e-12)
    np.testing.assert_allclose(step.rates[-1], step.rates[0][[2, 3, 0, 1]], atol=1e-12)


def test_time_is_in_the_walkers_unit(trial: WbdsTrial) -> None:
    step = human_step(trial)
    leg = step.body.leg_length
    assert step.n_knots == 41
    assert step.task.speed == pytest.approx(trial.row.speed / math.sqrt(PAPER_GRAVITY * leg))
    assert step.task.step_length == pytest.approx(trial.row.step_length / leg)
    assert step.duration == pytest.approx(step.task.step_length / step.task.speed)
    # The same duration from the cadence, in units of sqrt(L / g) (the table is consistent to 1 %).
    assert step.duration == pytest.approx(trial.row.step_time / math.sqrt(leg / PAPER_GRAVITY), rel=0.01)
    assert human_step(trial, n_intervals=10).n_knots == 21


def test_rates_are_the_derivatives_of_the_angles(trial: WbdsTrial) -> None:
    fine = human_step(trial, n_intervals=400)
    central = (fine.angles[2:] - fine.angles[:-2]) / (2 * fine.dt)
    np.testing.assert_allclose(fine.rates[1:-1], central, atol=2e-3 * np.abs(fine.rates).max())


@pytest.mark.parametrize(("subject", "speed"), ALL_TRIALS)
def test_moment_signs_give_the_known_joint_powers(subject: str, speed: str) -> None:
    """In the walker's convention, hip power is positive at loading (hip extensors
    shortening) and knee power negative in terminal swing (knee flexors braking)."""
    step = load_step(subject, speed)
    n = step.n_knots
    early = slice(0, int(0.4 * n))  # 0-20 % of the stride, the stance leg
    late = slice(int(0.7 * n), n)  # 85-100 % of the stride, the swing leg
    hip_power = step.torques[early, 0] * step.rates[early, 0]
    knee_power = step.torques[late, 3] * (step.rates[late, 3] - step.rates[late, 2])
    assert hip_power.sum() > 0
    assert knee_power.sum() < 0


@pytest.mark.parametrize(("subject", "speed"), ALL_TRIALS)
def test_the_pose_at_heel_strike_spans_the_tables_step(subject: str, speed: str) -> None:
    """The feet's distance from the mapped angles at heel strike is within 10 % of the
    table's step length: a check of the angle conventions against an independent measure."""
    step = load_step(subject, speed)
    assert step.checks.pose_step_length == pytest.approx(step.task.step_length, rel=0.10)


def test_pose_step_length_geometry() -> None:
    params = load_step("WBDS01", "T03").params
    beta = 0.3
    # Straight legs, stance at -beta, swing at +beta: the feet are 2 sin(beta) apart.
    assert pose_step_length(params, np.array([-beta, -beta, beta, beta])) == pytest.approx(2 * math.sin(beta))


def test_forces_are_in_body_weights(trial: WbdsTrial) -> None:
    step = human_step(trial, n_intervals=200)
    # Over a step, stance and swing feet cover the stride once: the mean total vertical
    # force is the measured weight, 1 body weight by construction.
    assert step.forces.total[:-1, 1].mean() == pytest.approx(1.0, abs=0.01)
    # The landing foot brakes: backward force on the stance foot early in the step.
    assert step.forces.stance[: step.n_knots // 5, 0].mean() < 0
    assert 0.9 < step.checks.weight_ratio < 1.0  # WBDS01: about 69-70 kg of 74.3 (data README)


def test_checks_flag_the_step_that_breaks_its_trend() -> None:
    flagged = load_step("WBDS02", "T05")
    assert flagged.checks.trend_departure == pytest.approx(-0.17, abs=0.02)
    assert any("departs -17 %" in note for note in flagged.checks.notes())
    assert not any("departs" in note for note in load_step("WBDS01", "T05").checks.notes())
    trend = load_step("WBDS02", "T05", step_length="trend")
    assert trend.task.step_length == pytest.approx(flagged.checks.trend_step_length)
    assert trend.task.speed == flagged.task.speed


def test_stance_knee_and_double_support_are_measured() -> None:
    checks = load_step("WBDS01", "T06").checks
    assert 15.0 < checks.stance_knee_flexion_deg < 21.0
    assert 0.55 < checks.stance_fraction < 0.7
    assert checks.double_support_step == pytest.approx(2 * (checks.stance_fraction - 0.5))


def test_bad_arguments(trial: WbdsTrial) -> None:
    with pytest.raises(ValueError, match="step_length must be 'table' or 'trend'"):
        human_step(trial, step_length="lab")
    with pytest.raises(ValueError, match="n_intervals must be an integer >= 1"):
        human_step(trial, n_intervals=0)
