"""``ioc-bench human``: bad input exits 2 with one line before any solve; one real small case."""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import pytest

from ioc_bench.cli import main
from ioc_bench.human import shipped_folder
from ioc_bench.human.track import HUMAN, HUMAN_SMOKE


def _run(capsys, *argv):
    with pytest.raises(SystemExit) as exc:
        main(list(argv))
    return exc.value.code, capsys.readouterr()


@pytest.fixture
def broken(tmp_path: Path) -> Path:
    """A copy of subject 01's shipped files whose T04 angle file lost half its rows."""
    src = shipped_folder()
    folder = tmp_path / "wbds"
    folder.mkdir()
    for path in src.iterdir():
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
        ((*CASE, "--algorithm", "nope"), "unknown algorithm"),
        ((*CASE, "--config", '{"no_such_field": 1}'), "no_such_field"),
        ((*CASE, "--starts", "0"), "must be >= 1"),
        ((*CASE, "--floor", "1,x,0"), "1,x,0"),
        (("human", "--suite", "human-smoke", "--config", '{"n_random": 2}'), "drop --config"),
        (("human", "--train", "T05"), "--subject and --train"),
        (("human", "--suite", "nope"), "unknown suite"),
        (("human", "--suite", "human-smoke", "--subject", "WBDS01"), "drop --subject"),
        ((*CASE, "--data", "{tmp}/missing"), "missing"),
        ((*CASE, "--data", "{tmp}/empty"), "no WBDS01walkT05ang.txt"),
        ((*CASE, "--data", "{broken}"), "WBDS01walkT04ang.txt"),
        ((*CASE, "--out", "{tmp}/a_file"), "--out"),
    ],
)
def test_bad_input_exits_2_with_one_line_before_any_solve(capsys, tmp_path, broken, monkeypatch, argv, message):
    import ioc_bench.human.track as track

    def no_solve(*_args, **_kwargs):
        raise AssertionError("a case was run on bad input")

    monkeypatch.setattr(track, "run_human_case", no_solve)
    (tmp_path / "empty").mkdir()
    (tmp_path / "a_file").write_text("x")
    argv = [a.replace("{tmp}", str(tmp_path)).replace("{broken}", str(broken)) for a in argv]
    code, out = _run(capsys, *argv)
    lines = out.err.strip().splitlines()
    assert code == 2 and len(lines) == 1, out.err
    assert "error" in lines[0] and message in lines[0]
    assert "Traceback" not in out.err and out.out == ""


def test_list_names_every_case(capsys) -> None:
    assert main(["human", "--list", "--json"]) == 0
    listing = json.loads(capsys.readouterr().out)
    assert [c["key"] for c in listing["human-smoke"]] == [s.key for s in HUMAN_SMOKE]
    assert [c["key"] for c in listing["human"]] == [s.key for s in HUMAN]


def test_one_small_case_end_to_end_and_resumed(capsys, tmp_path) -> None:
    """inverse-KKT trained at T05, predicting T04, one start per solve: the JSON carries the
    score, the figure is written, and a second run finds the result and solves nothing."""
    out = tmp_path / "out"
    argv = [*CASE, "--algorithm", "inverse-kkt", "--starts", "1", "--floor", "none", "--out", str(out), "--json"]
    assert main(argv) == 0
    report = json.loads(capsys.readouterr().out)
    assert report["status"] != "failed" and report["subject"] == "WBDS01"
    fit, pred = report["fit"], report["predictions"]["T04"]
    assert report["fit_rmse_deg"] == fit["fit_rmse_deg"] > 0
    for score in (fit, pred):
        method = score.get("fit_rmse_deg", score.get("prediction_rmse_deg"))
        if method is None:  # a failed forward solve is a recorded result: no RMSE, no skill
            assert score["status"] != "Solve_Succeeded" and score["skill"] is None
        else:
            assert score["floor_rmse_deg"] <= min(score["nominal_rmse_deg"], method)
    assert set(pred) >= {"prediction_rmse_deg", "nominal_rmse_deg", "floor_rmse_deg", "skill"}
    written = sorted(p.relative_to(out).as_posix() for p in out.rglob("*") if p.is_file())
    key = "inverse-kkt/WBDS01_T05__predict-T04__seed0__cfg"
    assert len(written) == 2 and all(w.startswith(key) for w in written)
    assert {Path(w).suffix for w in written} == {".json", ".png"}
    stored = json.loads((out / written[0]).read_text())
    assert len(stored["fit"]["angles"]["nominal"]) == 41  # each knot's four segment angles, for the figure
    assert set(stored["predictions"]["T04"]["angles"]) == {"estimate", "nominal"}

    import ioc_bench.human.track as track

    def no_solve(*_args, **_kwargs):
        raise AssertionError("a finished case was run again")

    track_run = track.run_human_case
    try:
        track.run_human_case = no_solve
        assert main(argv) == 0
    finally:
        track.run_human_case = track_run
    assert json.loads(capsys.readouterr().out)["fit_rmse_deg"] == report["fit_rmse_deg"]


def test_a_suite_resumes_finished_cases_and_writes_its_summary(capsys, tmp_path, monkeypatch) -> None:
    """human-smoke with both cases already in --out: nothing is solved, the summary is written."""
    import ioc_bench.human.track as track

    def no_solve(*_args, **_kwargs):
        raise AssertionError("a finished case was run again")

    monkeypatch.setattr(track, "run_human_case", no_solve)
    out = tmp_path / "out"
    for i, spec in enumerate(HUMAN_SMOKE):
        score = {"nominal_rmse_deg": 9.0, "floor_rmse_deg": 7.0, "skill": 0.5, "references": {}, "status": "ok"}
        record = spec.identity() | {
            "status": "converged",
            "fit": score | {"fit_rmse_deg": 7.0 + i},
            "predictions": {"T04": score | {"prediction_rmse_deg": 8.0 + 2 * i}},
            "wall_time": 1.0,
            "scoring_time": 1.0,
        }
        path = out / f"{spec.key}.json"
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(json.dumps(record))
    assert main(["human", "--suite", "human-smoke", "--out", str(out), "--json"]) == 0
    report = json.loads(capsys.readouterr().out)
    assert [c["algorithm"] for c in report["cases"]] == ["inverse-kkt", "bilevel"]
    summary = json.loads((out / "summary.json").read_text())
    assert summary["algorithms"]["inverse-kkt"]["beat_nominal"] == 1  # 8 deg against nominal 9
    assert summary["algorithms"]["bilevel"]["beat_nominal"] == 0  # 10 deg against nominal 9
    assert summary == {k: report[k] for k in ("suite", "algorithms")}
    assert "| inverse-kkt | 1 | 0 |" in (out / "summary.md").read_text()
