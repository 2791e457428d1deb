"""``ioc-bench replay``: exit codes, JSON report, outputs, one-line errors."""

from __future__ import annotations

import json
from dataclasses import replace

import numpy as np
import pytest

from ioc_bench import Demonstration, Task, optimize_gait
from ioc_bench.cli import main


@pytest.fixture(scope="module")
def demo_file(nominal_demo: Demonstration, tmp_path_factory) -> str:
    return str(nominal_demo.save(tmp_path_factory.mktemp("replay") / "nominal.npz"))


@pytest.fixture(scope="module")
def strong_torques_file(nominal_demo: Demonstration, tmp_path_factory) -> str:
    """The nominal step with its torques scaled by 1.1: physically wrong (they do not fit its motion)."""
    tr = nominal_demo.trajectory
    demo = replace(nominal_demo, trajectory=replace(tr, tau=tr.tau * 1.1))
    return str(demo.save(tmp_path_factory.mktemp("replay") / "strong.npz"))


@pytest.fixture(scope="module")
def heavy_file(heavy_legs_demo: Demonstration, tmp_path_factory) -> str:
    return str(heavy_legs_demo.save(tmp_path_factory.mktemp("replay") / "heavy.npz"))


def _bad_exit(argv: list[str], capsys) -> str:
    with pytest.raises(SystemExit) as exc:
        main(argv)
    assert exc.value.code == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1, err  # exactly one line
    return err


def test_json_report_and_outputs_next_to_the_demo(demo_file, capsys):
    code = main(["replay", demo_file, "--json", "--no-video", "--steps", "2"])
    report = json.loads(capsys.readouterr().out)
    assert code == 0
    assert set(report) >= {"checks", "inverse_dynamics", "open_loop", "closed_loop", "passed", "outputs"}
    assert [c["name"] for c in report["checks"]] == [
        "inverse_dynamics",
        "time_consistency",
        "ground_normal_force",
        "friction_cone",
        "swing_penetration",
        "knee_range",
    ]
    assert all(c["passed"] and c["reason"] == "" for c in report["checks"])
    assert report["passed"]
    assert report["inverse_dynamics"]["relative_residual"] < 1e-3
    assert report["closed_loop"]["steps_walked"] == 2
    assert 0 <= report["closed_loop"]["feedback_share"] < 0.2
    assert np.isfinite(report["open_loop"]["final_position_error"])
    assert report["outputs"]["plot"].endswith("nominal_replay.png")
    assert "video" not in report["outputs"]
    with open(report["outputs"]["plot"], "rb") as f:
        assert f.read(4) == b"\x89PNG"


def test_human_report_and_gif_in_out_dir(demo_file, tmp_path, capsys):
    code = main(["replay", demo_file, "--out", str(tmp_path), "--steps", "1"])
    out = capsys.readouterr().out
    assert code == 0
    lines = out.splitlines()
    for name in ("inverse_dynamics", "time_consistency", "ground_normal_force", "friction_cone"):
        assert sum(line.startswith(f"{name:<20} PASS  ") for line in lines) == 1, out
    assert any(line.startswith("knee_range           PASS  ") and "(<= 1e-06)" in line for line in lines)
    assert any(line.startswith("open loop            (reported)") for line in lines)
    assert any(line.startswith("closed loop          (reported)  1/1 steps, feedback share") for line in lines)
    assert "verdict  PASS: every physical check" in lines
    assert (tmp_path / "nominal_replay.gif").stat().st_size > 0
    assert (tmp_path / "nominal_replay.png").stat().st_size > 0


def test_wrong_model_fails_the_inverse_dynamics_check(heavy_file, capsys):
    code = main(["replay", heavy_file, "--model", "nominal", "--json", "--no-video", "--steps", "1"])
    report = json.loads(capsys.readouterr().out)
    assert code == 1
    assert report["model"] == "nominal"
    assert not report["inverse_dynamics"]["passed"]
    assert report["inverse_dynamics"]["relative_residual"] > 1e-3


def test_a_physically_wrong_step_fails_naming_its_cause(strong_torques_file, capsys):
    code = main(["replay", strong_torques_file, "--no-video", "--steps", "1"])
    lines = capsys.readouterr().out.splitlines()
    assert code == 1
    failed = [line for line in lines if " FAIL  " in line]
    assert len(failed) == 1 and failed[0].startswith("inverse_dynamics     FAIL  "), lines
    assert "torques inconsistent with the dynamics" in failed[0]
    assert "verdict  FAIL: inverse_dynamics" in lines


def test_a_step_that_cannot_be_replayed_is_judged_by_its_physics(nominal_demo, tmp_path, capsys):
    """Knots 5 % further apart: the tracking policy cannot follow it (its hip, interpolated
    with velocities that no longer fit, does not move steadily forward), so it is not
    replayed; the verdict names the timing, exit 1, not a usage error."""
    tr = nominal_demo.trajectory
    path = replace(nominal_demo, trajectory=replace(tr, dt=tr.dt * 1.05)).save(tmp_path / "slow.npz")
    code = main(["replay", str(path), "--no-video"])
    lines = capsys.readouterr().out.splitlines()
    assert code == 1
    assert [line.split()[0] for line in lines if " FAIL  " in line] == ["time_consistency"]
    assert any(line.startswith("open and closed loop (not run)  ") for line in lines)
    assert "verdict  FAIL: time_consistency" in lines
    assert not (tmp_path / "slow_replay.png").exists()


def test_a_fall_is_reported_and_exits_0(demo_file, capsys, monkeypatch):
    """Instability is not a physical error: a walk that falls (no feedback) still passes."""
    import envs.checks as checks
    from envs.tracking import PDGains

    real = checks.replay
    monkeypatch.setattr(checks, "replay", lambda *a, **k: real(*a, **k, gains=PDGains(kp=0.0, kd=0.0)))
    code = main(["replay", demo_file, "--json", "--no-video", "--steps", "3"])
    report = json.loads(capsys.readouterr().out)
    assert report["closed_loop"]["steps_walked"] < 3 and report["closed_loop"]["fall_reason"]
    assert not report["closed_loop"]["followed"]
    assert report["passed"] and code == 0


def test_missing_file_is_a_one_line_error(tmp_path, capsys):
    err = _bad_exit(["replay", str(tmp_path / "nope.npz")], capsys)
    assert "not found" in err


def test_malformed_file_is_a_one_line_error(tmp_path, capsys):
    garbage = tmp_path / "garbage.npz"
    garbage.write_bytes(b"not a zip file at all")
    _bad_exit(["replay", str(garbage)], capsys)
    incomplete = tmp_path / "incomplete.npz"
    np.savez(incomplete, meta=np.array("{}"))
    err = _bad_exit(["replay", str(incomplete), "--json"], capsys)
    assert "incomplete.npz" in err


def test_bad_arguments_exit_2(demo_file, tmp_path, capsys):
    _bad_exit(["replay", demo_file, "--steps", "0"], capsys)
    _bad_exit(["replay", demo_file, "--model", "heavy"], capsys)
    a_file = tmp_path / "file.txt"
    a_file.write_text("x")
    _bad_exit(["replay", demo_file, "--out", str(a_file)], capsys)


def test_several_files_one_json_line_each(demo_file, heavy_file, capsys):
    """The one-liner for a set of demonstrations: ``ioc-bench replay demos/*.npz``."""
    code = main(["replay", demo_file, heavy_file, "--model", "nominal", "--json", "--no-video", "--steps", "1"])
    lines = capsys.readouterr().out.splitlines()
    reports = [json.loads(line) for line in lines]
    assert [r["demo"] for r in reports] == [demo_file, heavy_file]
    assert [r["inverse_dynamics"]["passed"] for r in reports] == [True, False]  # the nominal model
    assert code == 1  # one of them failed


def test_several_files_human_summary(demo_file, capsys):
    code = main(["replay", demo_file, demo_file, "--no-video", "--steps", "1"])
    out = capsys.readouterr().out
    assert code == 0
    summary = out[out.index("summary  2/2 passed") :].splitlines()
    assert len(summary) == 3 and all(line.startswith(f"  PASS  {demo_file}: ") for line in summary[1:])


def test_a_bad_file_among_good_ones_stops_before_any_check(demo_file, tmp_path, capsys):
    err = _bad_exit(["replay", demo_file, str(tmp_path / "nope.npz")], capsys)
    assert "not found" in err
    assert "replay " not in capsys.readouterr().out


def test_mujoco_warnings_go_to_stderr_not_to_a_log_file(demo_file, tmp_path, capsys, monkeypatch):
    """Replay writes no MUJOCO_LOG.TXT in the current folder (outside --out).

    MuJoCo appends every warning to ``MUJOCO_LOG.TXT`` in the current folder unless a
    warning handler is set; one is forced here while the replay runs.
    """
    import mujoco

    import envs.checks as checks

    real = checks.replay

    def replay_after_a_warning(*args, **kwargs):
        model = mujoco.MjModel.from_xml_string(
            "<mujoco><worldbody><body><freejoint/><geom size='.1'/></body></worldbody></mujoco>"
        )
        data = mujoco.MjData(model)
        data.qpos[0] = np.nan
        mujoco.mj_step(model, data)  # "Nan, Inf or huge value in QPOS": MuJoCo warns
        return real(*args, **kwargs)

    monkeypatch.setattr(checks, "replay", replay_after_a_warning)
    cwd = tmp_path / "cwd"
    cwd.mkdir()
    monkeypatch.chdir(cwd)
    try:
        main(["replay", demo_file, "--out", str(tmp_path / "out"), "--no-video", "--steps", "1", "--json"])
    finally:
        mujoco.set_mju_user_warning(None)
    assert not any(cwd.iterdir()), list(cwd.iterdir())
    assert "MuJoCo warning: Nan, Inf or huge value in QPOS" in capsys.readouterr().err


def test_every_output_file_is_checked_before_the_first_replay(demo_file, tmp_path, capsys, monkeypatch):
    import envs.checks as checks

    monkeypatch.setattr(checks, "replay", lambda *a, **k: pytest.fail("replayed before the outputs were checked"))
    (tmp_path / "nominal_replay.gif").mkdir()
    err = _bad_exit(["replay", demo_file, "--out", str(tmp_path)], capsys)
    assert "nominal_replay.gif is a directory" in err


def test_a_demonstration_of_a_model_without_mujoco_model_is_one_line_before_any_replay(
    demo_file: str, tmp_path, capsys
):
    """A compass step has no MuJoCo model to be checked in: refused by name, exit 2, and
    refused before the walker's demonstration listed first is replayed (nothing written)."""
    from ioc_bench.model.compass import COMPASS

    compass = optimize_gait("nominal", task=Task(0.27), starts=1, seed=0, workers=1, model=COMPASS)
    other = str(compass.save(tmp_path / "compass.npz"))
    err = _bad_exit(["replay", demo_file, other, "--no-video", "--out", str(tmp_path / "out")], capsys)
    assert (
        "compass.npz: a demonstration of the 'compass' model cannot be replayed: only the walker and rolling-feet"
        in err
    )
    assert not (tmp_path / "out").exists()  # refused before the output folder is made


@pytest.mark.parametrize("command", [["replay"], ["export", "--format", "sto"]])
def test_an_ankle_feet_demonstration_is_refused_by_name_before_any_output(command, tmp_path, capsys):
    """The ankle model has no MuJoCo model: its demonstration (made up, nothing solved) is
    refused in one line, exit 2, before anything is written."""
    from synthetic import unsolved_demonstration

    from ioc_bench.model.feet import ANKLE_FEET

    path = str(unsolved_demonstration(ANKLE_FEET).save(tmp_path / "ankle.npz"))
    err = _bad_exit([command[0], path, *command[1:], "--out", str(tmp_path / "out")], capsys)
    assert "ankle.npz: a demonstration of the 'ankle-feet' model cannot be replayed" in err
    assert not (tmp_path / "out").exists()
