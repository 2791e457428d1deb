"""The three MuJoCo checks of a demonstration, and what the replay writes."""

from __future__ import annotations

import numpy as np
import pytest
from PIL import Image

from envs.checks import (
    FEEDBACK_SHARE_LIMIT,
    ID_TOLERANCE,
    closed_loop_replay,
    inverse_dynamics_check,
    track_demonstrations,
)
from envs.checks.closed_loop import CHECK_CONTROL_DT
from envs.plots import plot_comparison, write_animation
from envs.reference import DemoReference
from envs.tracking import PDGains
from ioc_bench import Demonstration, WalkerParams


def test_inverse_dynamics_matches_the_optimizer(nominal_demo: Demonstration):
    result = inverse_dynamics_check(nominal_demo)
    assert result.passed
    assert result.relative_residual < ID_TOLERANCE  # the acceptance figure: 0.1 % of peak torque
    assert result.relative_residual < 1e-8  # same model: only round-off remains (measured ~4e-12)
    assert result.residual.shape == (nominal_demo.trajectory.n_knots, 7)
    assert result.peak_torque == pytest.approx(np.abs(nominal_demo.trajectory.tau).max())


def test_inverse_dynamics_tells_a_wrong_model(heavy_legs_demo: Demonstration):
    own = inverse_dynamics_check(heavy_legs_demo)
    assert own.passed and own.relative_residual < 1e-8
    wrong = inverse_dynamics_check(heavy_legs_demo, WalkerParams())
    assert not wrong.passed
    assert wrong.relative_residual > ID_TOLERANCE


def test_open_loop_starts_on_the_demonstration_and_reports_its_drift(nominal_demo, nominal_open_loop):
    ol = nominal_open_loop
    ref = DemoReference.of(nominal_demo)
    assert ol.qpos.shape == ol.qpos_ref.shape == (nominal_demo.trajectory.n_knots, 7)
    assert ol.position_error[0] == pytest.approx(0.0, abs=1e-12)
    assert ol.qpos_ref == pytest.approx(ref.qpos)
    assert np.isfinite(ol.final_position_error) and np.isfinite(ol.final_velocity_error)
    assert ol.final_position_error == pytest.approx(ol.position_error[-1])
    # The physics step divides the knot spacing, so every knot is sampled exactly.
    assert ref.dt / ol.timestep == pytest.approx(round(ref.dt / ol.timestep), abs=1e-9)
    # Not a pass/fail figure, but a sanity bound: one step does not drift far (measured 6.4e-2
    # in v2 with the frictionless grazing swing foot; 0.49 when the graze was a scuff, v1).
    assert ol.final_position_error < 0.1


def test_closed_loop_walks_ten_steps_mostly_on_feed_forward(nominal_demo, nominal_closed_loop):
    cl = nominal_closed_loop
    assert cl.steps_walked == 10, cl.fall_reason
    assert cl.fall_reason is None
    assert cl.feedback_share < FEEDBACK_SHARE_LIMIT
    assert cl.passed
    assert cl.tracking_rms < 0.01  # rad (measured 3.8e-3)
    assert cl.control_dt <= CHECK_CONTROL_DT
    # Legs swap at every heel strike and steps last about as long as the demonstration's.
    assert len(cl.heel_strikes) == 10
    assert set(cl.stance) == {"a", "b"}
    durations = np.diff((0.0, *cl.heel_strikes))
    assert durations == pytest.approx(np.full(10, nominal_demo.trajectory.duration), rel=0.1)
    # The stance foot stays on the floor (measured: at every control step).
    assert cl.stance_contact > 0.95
    # The swing foot grazes the ground mid-swing (as the demonstration's does), and no graze
    # was taken for a heel strike (ten strikes, ten steps of the demonstration's duration).
    assert cl.grazes >= 1


def test_feedback_share_is_the_documented_ratio(nominal_closed_loop):
    cl = nominal_closed_loop
    # Every decision but the last one (taken after the walk, never applied) counts.
    ff, fb = np.abs(cl.tau_ff[:-1]).sum(), np.abs(cl.tau_fb[:-1]).sum()
    assert cl.feedback_share == pytest.approx(fb / (ff + fb), rel=1e-12)
    err = cl.joints_ref[:-1] - cl.joints[:-1]
    assert cl.tracking_rms == pytest.approx(np.sqrt(np.mean(err**2)), rel=1e-12)


def test_demonstration_of_another_model_replays_on_its_own_model(heavy_legs_demo: Demonstration):
    cl = closed_loop_replay(heavy_legs_demo, steps=10)
    assert cl.steps_walked == 10, cl.fall_reason
    assert cl.feedback_share < FEEDBACK_SHARE_LIMIT


def test_a_fall_is_reported_not_raised(nominal_demo: Demonstration):
    cl = closed_loop_replay(nominal_demo, steps=10, gains=PDGains(kp=0.0, kd=0.0))
    assert cl.steps_walked < 10
    assert cl.fall_reason
    assert not cl.passed


def test_track_demonstrations_takes_files_and_objects(nominal_demo: Demonstration, tmp_path):
    path = nominal_demo.save(tmp_path / "demo.npz")
    by_file, by_object = track_demonstrations([path, nominal_demo], steps=1)
    assert by_file.steps_walked == by_object.steps_walked == 1
    assert by_file.heel_strikes == by_object.heel_strikes


def test_bad_steps_are_rejected(nominal_demo: Demonstration):
    with pytest.raises(ValueError, match="steps"):
        closed_loop_replay(nominal_demo, steps=0)


def test_plot_and_animation_are_written(nominal_demo, nominal_open_loop, tmp_path):
    short = closed_loop_replay(nominal_demo, steps=1)
    png = plot_comparison(nominal_demo, nominal_open_loop, short, tmp_path / "cmp.png")
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    gif = write_animation(short, nominal_demo.params, tmp_path / "walk.gif")
    with Image.open(gif) as im:
        assert im.format == "GIF"
        assert im.n_frames > 10
