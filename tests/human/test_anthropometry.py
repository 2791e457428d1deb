"""The subject's walker: lengths from markers, Winter's masses, in the walker's units."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from ioc_bench.human.anthropometry import (
    HAT_LENGTH,
    WINTER,
    body_lengths,
    hip_joint_centres,
    subject_body,
    subject_walker,
)
from ioc_bench.human.wbds import STATIC_MARKERS, StaticMarkers, WbdsData, WbdsDataError

WIDTH, DEPTH = 250.0, 180.0  # pelvis, mm
THIGH, SHANK, ANKLE = 400.0, 420.0, 80.0


def _v(*xyz: float) -> np.ndarray:
    return np.array(xyz, dtype=float)


def _static(knee_drop: float = THIGH) -> StaticMarkers:
    """A person standing straight, pelvis level, facing +X (lab axes X forward, Y up, Z right)."""
    mid = np.array([0.0, 1000.0, 0.0])
    pos = {
        "R.ASIS": mid + _v(0, 0, WIDTH / 2),
        "L.ASIS": mid - _v(0, 0, WIDTH / 2),
        "R.PSIS": mid + _v(-DEPTH, 0, 40),
        "L.PSIS": mid + _v(-DEPTH, 0, -40),
    }
    hips = hip_joint_centres(StaticMarkers(Path("x"), 1, pos))
    for side, sign in (("R", 1), ("L", -1)):
        hip = hips[side]
        knee = hip - _v(0, knee_drop, 0)
        ankle = knee - _v(0, SHANK, 0)
        pos[f"{side}.Knee"] = knee + _v(0, 0, sign * 50)
        pos[f"{side}.Knee.Medial"] = knee - _v(0, 0, sign * 50)
        pos[f"{side}.Ankle"] = ankle + _v(0, 0, sign * 35)
        pos[f"{side}.Ankle.Medial"] = ankle - _v(0, 0, sign * 35)
        pos[f"{side}.MT2"] = ankle + _v(150, -40, 0)
        pos[f"{side}.Heel"] = ankle + _v(-50, -30, 0)
    # The floor (Y = 0) ANKLE below the ankle centres.
    shift = np.array([0, hips["R"][1] - THIGH - SHANK - ANKLE, 0])
    pos = {k: v - shift for k, v in pos.items()}
    assert set(pos) == set(STATIC_MARKERS)
    return StaticMarkers(Path("synthetic_static.txt"), 1, pos)


def test_harrington_hip_centre_on_a_level_pelvis() -> None:
    static = _static()
    hips = hip_joint_centres(static)
    mid = (static["R.ASIS"] + static["L.ASIS"]) / 2
    # Harrington et al. 2007: posterior 0.24 PD + 9.9, inferior 0.30 PW + 10.9, lateral 0.33 PW + 7.3 (mm).
    expected = mid + _v(-(0.24 * DEPTH + 9.9), -(0.30 * WIDTH + 10.9), 0.33 * WIDTH + 7.3)
    np.testing.assert_allclose(hips["R"], expected, atol=1e-9)
    assert hips["L"][2] == pytest.approx(mid[2] - (0.33 * WIDTH + 7.3))


def test_lengths_of_a_known_standing_pose() -> None:
    lengths = body_lengths(_static())
    assert lengths.thigh == pytest.approx(THIGH / 1000)
    assert lengths.shank == pytest.approx(SHANK / 1000)
    assert lengths.ankle_height == pytest.approx(ANKLE / 1000)
    assert lengths.leg_length == pytest.approx((THIGH + SHANK + ANKLE) / 1000)
    assert lengths.foot_com_height == pytest.approx((ANKLE + ANKLE - 40) / 2000)
    assert lengths.side_difference == pytest.approx(0.0, abs=1e-12)


def test_wbds01_lengths_match_the_data_readme() -> None:
    """The data's README measured thigh 0.386, shank 0.410, ankle height 0.082 m for WBDS01."""
    lengths = body_lengths(WbdsData().trial("WBDS01", "T05").static)
    assert lengths.thigh == pytest.approx(0.386, abs=0.001)
    assert lengths.shank == pytest.approx(0.410, abs=0.001)
    assert lengths.ankle_height == pytest.approx(0.082, abs=0.001)


def test_implausible_markers_are_refused() -> None:
    with pytest.raises(WbdsDataError, match=r"synthetic_static\.txt: thigh 0\.900 m is outside"):
        body_lengths(_static(knee_drop=900.0))
    with pytest.raises(WbdsDataError, match="not one above the other"):
        body_lengths(_static(knee_drop=-100.0))


@pytest.mark.parametrize("subject", ["WBDS01", "WBDS02", "WBDS03"])
def test_subject_walker_is_in_walker_units(subject: str) -> None:
    trial = WbdsData().trial(subject, "T04")
    body = subject_body(trial.static, trial.row)
    params = body.walker()
    assert params.leg_length == pytest.approx(1.0)
    assert params.total_mass == pytest.approx(1.0)
    for seg in (params.torso, params.thigh, params.shank):
        assert seg.inertia > 0 and 0 < seg.com < seg.length
    assert params.torso.length == pytest.approx(HAT_LENGTH * trial.row.height / body.leg_length)
    assert params.thigh.com == pytest.approx(WINTER["thigh"].com * params.thigh.length)
    # The shank carries the foot: its centre of mass lies below Winter's leg-alone one.
    assert params.shank.com > WINTER["leg"].com * body.lengths.shank / body.leg_length
    # Close to the default walker, whose masses come from the same table (docs/spec.md).
    assert params.thigh.length == pytest.approx(0.46, abs=0.03)
    assert params.torso.inertia == pytest.approx(0.05, rel=0.2)


def test_subject_walker_refuses_a_height_below_the_leg() -> None:
    with pytest.raises(ValueError, match="must exceed the leg length"):
        subject_walker(body_lengths(_static()), 0.5)
