"""The command line: one-line errors with exit code 2, JSON reports, written files."""

from __future__ import annotations

import json
import subprocess
import sys

import pytest

from ioc_bench import __version__
from ioc_bench.cli import main


def _run(capsys, *argv):
    with pytest.raises(SystemExit) as exc:
        main(list(argv))
    return exc.value.code, capsys.readouterr()


@pytest.mark.parametrize(
    "argv",
    [
        ["gait", "--weights", "bogus"],
        ["gait", "--weights", "1,-1,1"],
        ["gait", "--weights", "nan,1,1"],
        ["gait", "--weights", "1,2"],
        ["gait", "--speed", "0"],
        ["gait", "--speed", "-1"],
        ["table1", "--speed", "abc"],
        ["ioc", "--algorithm", "nope"],
        ["ioc", "--condition", "nope"],
        ["ioc", "--weights", "nope"],
        ["ioc", "--config", "[1, 2]"],
        ["no-such-command"],
    ],
)
def test_bad_arguments_exit_2_with_one_line(capsys, argv):
    code, out = _run(capsys, *argv)
    assert code == 2
    lines = out.err.strip().splitlines()
    assert len(lines) == 1 and "error" in lines[0]
    assert "Traceback" not in out.err


def test_unknown_names_list_the_valid_ones(capsys):
    _, out = _run(capsys, "ioc", "--algorithm", "nope")
    assert "log-barrier" in out.err and "analytic-center" in out.err
    _, out = _run(capsys, "ioc", "--condition", "nope")
    assert "ideal" in out.err and "distractor" in out.err


def test_gait_json_report_and_files(capsys, tmp_path):
    out_file = tmp_path / "demo.npz"
    assert main(["gait", "--weights", "1,10,1", "--starts", "2", "--out", str(out_file), "--json"]) == 0
    report = json.loads(capsys.readouterr().out)
    assert report["solver"]["success"] and report["solver"]["max_violation"] <= 1e-6
    assert set(report["features"]) == {"hip", "knee", "dtau", "torso", "steplen", "footheight"}
    assert {"status", "iterations", "wall_time"} <= set(report["solver"])
    assert out_file.is_file() and out_file.with_suffix(".png").stat().st_size > 10_000


def test_algorithms_lists_descriptions(capsys):
    assert main(["algorithms"]) == 0
    out = capsys.readouterr().out
    assert "log-barrier" in out and "as printed" in out


def test_ioc_json(capsys, tmp_path, ideal_nominal_cached):
    out = tmp_path / "r.json"
    argv = ["ioc", "--algorithm", "analytic-center", "--weights", "nominal", "--out", str(out), "--json"]
    assert main(argv) == 0
    report = json.loads(capsys.readouterr().out)
    assert report["weight_error"] < 0.01 and report["n_solves"] > 0
    saved = json.loads(out.read_text())
    assert saved["weight_error"] == report["weight_error"] and len(saved["history"]) == report["iterations"]
    assert {k: report[k] for k in saved} == saved  # everything the result file holds: transfer, coverage, region
    assert report["transfer"]["speed"] == 0.34 and report["covered"] is not None and report["uncertainty"]
    assert out.with_suffix(".png").is_file()


def test_solver_timing_is_its_own_command_and_a_missing_command_module_fails_loudly(monkeypatch):
    from ioc_bench import cli

    assert "solver_timing" in cli.COMMANDS and "speed" not in cli.COMMANDS and "bench" not in cli.COMMANDS
    monkeypatch.setattr(cli, "COMMANDS", (*cli.COMMANDS, "no_such_command_module"))
    with pytest.raises(ModuleNotFoundError, match="no_such_command_module"):
        cli.build_parser()


def test_version_prints_the_package_version_and_exits_0(capsys):
    code, out = _run(capsys, "--version")
    assert code == 0
    assert out.out == f"ioc-bench {__version__}\n" and out.err == ""


def test_version_from_a_shell(tmp_path):
    argv = [sys.executable, "-m", "ioc_bench.cli", "--version"]
    proc = subprocess.run(argv, capture_output=True, text=True, cwd=tmp_path, check=False)
    assert proc.returncode == 0 and proc.stdout == f"ioc-bench {__version__}\n"
