"""``ioc-bench human`` (one case) and ``ioc-bench run --suite human-smoke``: bad input exits 2
with one line before any solve; one real small case, written, locked, resumed."""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import pytest

from ioc_bench.cli import main
from ioc_bench.human import shipped_folder
from ioc_bench.human.case import HumanCaseSpec
from ioc_bench.runner import run as runner
from ioc_bench.runner.results import ResultFileError, results_directory, select_results


def _run(capsys, *argv):
    with pytest.raises(SystemExit) as exc:
        main(list(argv))
    return exc.value.code, capsys.readouterr()


@pytest.fixture
def broken(tmp_path: Path) -> Path:
    """A copy of subject 01's shipped files whose T04 angle file lost half its rows."""
    folder = tmp_path / "wbds"
    folder.mkdir()
    for path in shipped_folder().iterdir():
        if path.name.startswith("WBDS01") or path.suffix == ".csv":
            shutil.copy(path, folder / path.name)
    ang = folder / "WBDS01walkT04ang.txt"
    ang.write_text("\n".join(ang.read_text().split("\n")[:50]))
    return folder


CASE = ("human", "--subject", "WBDS01", "--train", "T05", "--predict", "T04")


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (("human", "--subject", "WBDS99", "--train", "T05", "--predict", "T04"), "no WBDS99walkT05ang.txt"),
        (("human", "--subject", "S1", "--train", "T05"), "unknown subject code"),
        (("human", "--subject", "WBDS01", "--train", "T11"), "unknown speed code"),
        (("human", "--subject", "WBDS01", "--train", "T05", "--predict", "T04,T99"), "unknown speed code"),
        (("human", "--subject", "WBDS01", "--train", "T05", "--predict", "T04,T05"), "also a predicted speed"),
        (("human", "--subject", "WBDS01", "--train", "T05", "--predict", "T07"), "no WBDS01walkT07ang.txt"),
        (("human", "--subject", "WBDS01", "--train", "T05,T04", "--predict", "T04"), "T04 is also a predicted speed"),
        (("human", "--subject", "WBDS01", "--train", "T05,T05"), "training speed is repeated"),
        ((*CASE, "--population", "WBDS01"), "its own population"),
        ((*CASE, "--population", "WBDS09"), "WBDS09"),
        ((*CASE, "--algorithm", "nope"), "unknown algorithm"),
        ((*CASE, "--config", '{"no_such_field": 1}'), "no_such_field"),
        ((*CASE, "--starts", "0"), "must be >= 1"),
        ((*CASE, "--floor", "1,x,0"), "1,x,0"),
        (("human", "--train", "T05"), "--subject and --train"),
        (("human", "--suite", "human-smoke"), "ioc-bench run --suite human-smoke"),
        ((*CASE, "--data", "{tmp}/missing"), "missing"),
        ((*CASE, "--data", "{tmp}/empty"), "no WBDS01walkT05ang.txt"),
        ((*CASE, "--data", "{broken}"), "WBDS01walkT04ang.txt"),
        ((*CASE, "--out", "{tmp}/a_file"), "--out"),
        (("run", "--suite", "human-smoke", "--algorithm", "bilevel", "--data", "{broken}"), "WBDS01walkT04ang.txt"),
        (("run", "--suite", "smoke", "--data", "{broken}"), "a synthetic suite"),
        ((*CASE, "--model", "nope"), "unknown gait model 'nope'; human steps map to the models walker, rolling-feet"),
        ((*CASE, "--model", "compass"), "human steps map to the models walker, rolling-feet, not 'compass'"),
        (("run", "--suite", "human-smoke", "--algorithm", "bilevel", "--model", "compass"), "not 'compass'"),
        ((*CASE, "--task", "nope"), "unknown task 'nope'; a human case's task is one of speed, speed-and-step"),
        ((*CASE, "--basis", "rich"), "unknown cost basis 'rich'; valid: effort, effort-work, energetics"),
    ],
)
def test_bad_input_exits_2_with_one_line_before_any_solve(capsys, tmp_path, broken, monkeypatch, argv, message):
    def no_solve(*_args, **_kwargs):
        raise AssertionError("a case was run on bad input")

    monkeypatch.setattr(HumanCaseSpec, "run", no_solve)
    monkeypatch.setattr(runner, "prepare_inputs", no_solve)
    (tmp_path / "empty").mkdir()
    (tmp_path / "a_file").write_text("x")
    argv = [a.replace("{tmp}", str(tmp_path)).replace("{broken}", str(broken)) for a in argv]
    code, out = _run(capsys, *argv)
    lines = out.err.strip().splitlines()
    assert code == 2 and len(lines) == 1, out.err
    assert "error" in lines[0] and message in lines[0]
    assert "Traceback" not in out.err and out.out == ""


def test_run_lists_the_human_suites(capsys) -> None:
    assert main(["run", "--list", "--json"]) == 0
    suites = {s["name"]: s for s in json.loads(capsys.readouterr().out)["suites"]}
    assert suites["human"]["cases"] == 27 == suites["human-given-step"]["cases"] and suites["human-smoke"]["cases"] == 1
    assert suites["human-rolling-feet"]["cases"] == 1 and suites["human-rolling-feet"]["model"] == "rolling-feet"


def test_one_small_case_end_to_end_locked_and_resumed(capsys, tmp_path, monkeypatch) -> None:
    """inverse-KKT trained at T05, predicting T04, one start per solve: the record carries the
    scores and the copy baseline, the figure is written beside it, the folder is held while
    it runs, and a second run finds the record and solves nothing."""
    out = tmp_path / "out"
    argv = [*CASE, "--algorithm", "inverse-kkt", "--starts", "1", "--floor", "none", "--out", str(out), "--json"]
    assert main(argv) == 0
    report = json.loads(capsys.readouterr().out)
    assert report["status"] != "failed" and report["track"] == "human"
    fit, pred = report["scores"]["T05"], report["scores"]["T04"]
    assert fit["role"] == "fit" and pred["role"] == "prediction" and pred["copy_from"] == "T05"
    assert pred["copy_rmse_deg"] > 0 and pred["copy_adaptation_deg"] == pred["copy_rmse_deg"]
    # carried from T05 by continuation, its step length free, beside the cold start and the baselines
    assert pred["continued_from"] == "T05" and pred["continuation_solves"] >= 3 and report["task"] == "speed"
    assert pred["change_r2"] == pytest.approx(1 - (pred["adaptation_deg"] / pred["copy_adaptation_deg"]) ** 2)
    assert pred["step_length_walker"] > 0 and pred["step_length_error"] >= 0 and pred["cold_rmse_deg"] > 0
    assert pred["population_rmse_deg"] > 0 and pred["power_law_step_length_error"] >= 0
    written = sorted(p.relative_to(out).as_posix() for p in out.rglob("*") if p.is_file())
    key = "inverse-kkt/WBDS01__train-T05__predict-T04__seed0__task-speed__cfg"
    assert len(written) == 2 and all(w.startswith(key) for w in written)
    assert {Path(w).suffix for w in written} == {".json", ".png"}
    assert [r.subject for r in select_results(out)] == ["WBDS01"]  # the board finds it by its name

    def no_solve(*_args, **_kwargs):
        raise AssertionError("a finished case was run again")

    monkeypatch.setattr(HumanCaseSpec, "run", no_solve)
    (out / written[1]).unlink()  # the figure of a run killed after its record
    assert main(argv) == 0
    assert json.loads(capsys.readouterr().out)["scores"]["T04"]["rmse_deg"] == pred["rmse_deg"]
    assert (out / written[1]).is_file()  # written by the run that resumed
    with results_directory(out), pytest.raises(SystemExit) as exc:
        main(argv)
    assert exc.value.code == 2 and "another run is writing" in capsys.readouterr().err
    with pytest.raises(ResultFileError):
        results = json.loads((out / written[0]).read_text())
        results["scores"]["T04"]["skill"] = 99.0
        (out / written[0]).write_text(json.dumps(results))
        from ioc_bench.runner.results import read_result

        read_result(out / written[0], out)


def test_one_small_rolling_feet_case_end_to_end(capsys, tmp_path) -> None:
    """The same small case on the walker with rolling feet: its record and figure are filed
    under the model's key, and the steps it scores are the model's (not the walker's)."""
    out = tmp_path / "out"
    argv = [*CASE, "--algorithm", "inverse-kkt", "--starts", "1", "--floor", "none", "--model", "rolling-feet"]
    assert main([*argv, "--out", str(out), "--json"]) == 0
    report = json.loads(capsys.readouterr().out)
    assert report["status"] != "failed" and report["model"] == "rolling-feet"
    assert report["features"] == ["hip", "knee", "dtau"]
    pred = report["scores"]["T04"]
    assert pred["role"] == "prediction" and pred["copy_from"] == "T05" and pred["rmse_deg"] > 0
    written = sorted(p.relative_to(out).as_posix() for p in out.rglob("*") if p.is_file())
    assert [Path(w).suffix for w in written] == [".json", ".png"]
    assert all("__model-rolling-feet__task-speed__cfg" in w for w in written)
    walker = HumanCaseSpec("WBDS01", "T05", ("T04",), "inverse-kkt", starts=1, floor_weights=())
    assert not (out / f"{walker.key}.json").exists()
