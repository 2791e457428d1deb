"""The leaderboard is regenerated from result files; CIs appear with 3+ seeds per case."""

from __future__ import annotations

import dataclasses
import hashlib
import json

import numpy as np
import pytest
from synthetic import estimate_with_error

from ioc_bench.cli import main
from ioc_bench.runner.leaderboard import markdown, write_leaderboard
from ioc_bench.runner.results import load_results, write_result
from ioc_bench.synthetic.board import demo_spread, penalised_is_largest, summarise
from ioc_bench.synthetic.case import CaseSpec, failure
from ioc_bench.synthetic.results import parse_result


def _result(algorithm, weight_set, condition, seed, weights, error):
    """A converged result: ``weights`` (normalised) if given, else weights ``error`` from the truth."""
    base = failure(CaseSpec(algorithm, weight_set, condition, seed), "placeholder")
    true = np.array(base.true_weights)
    w = estimate_with_error(true, error) if weights is None else np.asarray(weights) / np.linalg.norm(weights)
    fields = base.to_dict() | {
        "status": "converged",
        "reason": "",
        "weights": tuple(float(x) for x in w),
        "weight_error": float(np.mean(np.abs(np.asarray(w) - true))),
        "trajectory_error": 10 * error,
        "n_solves": 7,
        "wall_time": 1.5,
    }
    return parse_result(fields)


@pytest.fixture
def results_dir(tmp_path):
    rng = np.random.default_rng(1)
    for seed in range(3):
        for ws in ("nominal", "penalize-hip"):
            for cond in ("ideal", "noise"):
                spec = CaseSpec("algo", ws, cond, seed)
                write_result(tmp_path, spec, _result("algo", ws, cond, seed, None, float(rng.uniform(0.01, 0.05))))
    write_result(
        tmp_path, CaseSpec("algo", "nominal", "mass", 0), failure(CaseSpec("algo", "nominal", "mass", 0), "boom")
    )
    return tmp_path


def test_summary_cells_and_bootstrap_ci(results_dir):
    results = load_results(results_dir)
    cells = {c.condition: c for c in summarise(results)}
    ideal = cells["ideal"]
    errors = [r.weight_error for r in results if r.condition == "ideal"]
    assert ideal.cases == 6 and ideal.failures == 0 and ideal.seeds == (0, 1, 2)
    assert ideal.weight_error == pytest.approx(np.mean(errors))
    low, high = ideal.weight_error_ci
    assert low < ideal.weight_error < high and min(errors) <= low and high <= max(errors)
    assert ideal.largest_recovered == 3 and ideal.largest_checked == 3
    mass = cells["mass"]
    assert mass.failures == 1 and np.isnan(mass.weight_error) and mass.weight_error_ci is None


def test_written_files_state_method_seeds_and_versions(results_dir, tmp_path):
    out = tmp_path / "board"
    md_path, json_path, *_ = write_leaderboard(load_results(results_dir), out, source="results/")
    md = md_path.read_text()
    assert "never edited by hand" in md and "**Method.**" in md and "**Seeds:** 0, 1, 2" in md
    assert "casadi" in md and "percentile bootstrap" in md and "| algo | walker | 0.0" in md  # the grid's row
    cells = (out / "cells.csv").read_text().splitlines()
    assert len(cells) == 4 and cells[0].startswith("algorithm,family,label,condition,cases,")  # 3 cells
    assert "resamples the seeds within each weight set" in md  # the header says what the interval covers
    data = json.loads(json_path.read_text())
    assert {c["condition"] for c in data["cells"]} == {"ideal", "noise", "mass"}
    assert len(data["cases"]) == 13
    assert data["schema"] == "ioc-bench/leaderboard" and data["schema_version"] == 2 and "versions" not in data


def test_a_board_states_what_its_cases_ran_with_not_what_drew_it(results_dir, tmp_path):
    """The header and ``provenance`` are the cases' own commits and versions (the drawing
    machine's are nowhere); a case recorded before provenance counts as not recorded."""
    ran = {"commit": "0123456789abcdef0123456789abcdef01234567", "dirty": False, "versions": {"numpy": "1.0"}}
    results = load_results(results_dir)
    results = [dataclasses.replace(r, provenance=ran if k else {}) for k, r in enumerate(results)]
    md_path, json_path, *_ = write_leaderboard(results, tmp_path / "board")
    md, data = md_path.read_text(), json.loads(json_path.read_text())
    assert (
        "**Cases ran with:** commit `0123456789ab` (12 cases); not recorded (1 case). "
        "**Versions:** numpy 1.0 (12 cases); not recorded (1 case)"
    ) in md
    assert "casadi" not in md.split("## ")[0]  # the header: the machine drawing the board has casadi, its cases not
    assert data["provenance"] == {
        "cases": 13,
        "not_recorded": 1,
        "commits": [{"commit": ran["commit"], "dirty": False, "cases": 12}],
        "versions": [{"versions": {"numpy": "1.0"}, "cases": 12}],
    }
    assert [c["provenance"] for c in data["cases"]] == [{}] + [ran] * 12


def test_penalised_weight_check():
    r = _result("a", "penalize-hip", "noise", 0, (0.9, 0.3, 0.2), 0.1)
    assert penalised_is_largest(r) is True
    assert penalised_is_largest(_result("a", "penalize-knee", "noise", 0, (0.9, 0.3, 0.2), 0.1)) is False
    assert penalised_is_largest(_result("a", "nominal", "noise", 0, (0.9, 0.3, 0.2), 0.1)) is None


def test_cli(results_dir, tmp_path, capsys):
    assert main(["leaderboard", str(results_dir), "--out", str(tmp_path / "lb"), "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["files"]
    with pytest.raises(SystemExit) as exc:
        main(["leaderboard", str(tmp_path / "missing")])
    assert exc.value.code == 2 and len(capsys.readouterr().err.strip().splitlines()) == 1


def test_configs_never_share_a_cell_and_the_header_names_each(tmp_path, make_result):
    """Results of two configs of one algorithm are two rows; one spelling out defaults is the defaults' row."""
    defaults = make_result("log-barrier", "nominal", "ideal", 0, weight_error=0.1)
    spelled = make_result("log-barrier", "nominal", "ideal", 1, config={"n_random": 10}, weight_error=0.3)
    quick = make_result("log-barrier", "nominal", "ideal", 0, config={"n_random": 1, "max_iterations": 2})
    cells = summarise([defaults, spelled, quick])
    assert [(c.label, c.cases) for c in cells] == [("log-barrier", 2), ("log-barrier [cfg 05519c9f]", 1)]
    assert cells[0].weight_error == pytest.approx(0.2) and cells[1].config == {"max_iterations": 2, "n_random": 1}
    write_result(tmp_path, CaseSpec("log-barrier", "nominal", "ideal", 0), defaults)
    write_result(tmp_path, CaseSpec("log-barrier", "nominal", "ideal", 0, {"n_random": 1, "max_iterations": 2}), quick)
    md = markdown(load_results(tmp_path))
    assert "`log-barrier`: the algorithm's defaults (in full: `" in md  # e.g. where its forward solves start
    assert '`log-barrier [cfg 05519c9f]`: defaults except `{"max_iterations": 2, "n_random": 1}`' in md
    assert "| log-barrier | walker |" in md and "| log-barrier [cfg 05519c9f] | walker |" in md


def test_the_files_are_written_together_or_not_at_all(results_dir, tmp_path, monkeypatch):
    from ioc_bench import fileio

    out = tmp_path / "board"
    md_path, json_path, *_ = write_leaderboard(load_results(results_dir), out)
    old = (md_path.read_bytes(), json_path.read_bytes())
    assert json.loads(old[1])["readme_sha256"] == hashlib.sha256(old[0]).hexdigest()
    real = fileio._stage

    def fail_on_json(path, write, link_final):
        if path.name == "leaderboard.json":
            raise OSError("disk full")
        return real(path, write, link_final)

    monkeypatch.setattr(fileio, "_stage", fail_on_json)
    with pytest.raises(OSError):
        write_leaderboard(load_results(results_dir)[:3], out)
    assert (md_path.read_bytes(), json_path.read_bytes()) == old
    written = ["README.md", "cases.csv", "cells.csv", "human_cases.csv", "leaderboard.html", "leaderboard.json"]
    assert sorted(p.name for p in out.iterdir()) == written


def test_a_board_written_into_the_results_is_not_read_back(results_dir, capsys):
    board = results_dir / "board"
    for _ in range(2):
        assert main(["leaderboard", str(results_dir), "--out", str(board), "--json"]) == 0
        report = json.loads(capsys.readouterr().out)
        assert sum(c["cases"] for c in report["cells"]) == 13


def test_no_interval_where_failures_leave_too_few_replicates(make_result):
    """Three seeds of which two failed leave one value per weight set: no interval, only the mean."""
    results = [
        make_result(weight_set=w, seed=s, failed=s > 0, weight_error=0.1 * (i + 1))
        for i, w in enumerate(("nominal", "penalize-hip"))
        for s in (0, 1, 2)
    ]
    (cell,) = summarise(results)
    assert cell.failures == 4 and cell.weight_error == pytest.approx(0.15)
    assert cell.weight_error_ci is None


def test_other_weight_sets_get_their_own_row(make_result):
    """The unseen suite's weight sets (one seed) never share a row with the paper's four (three seeds)."""
    paper = [make_result(weight_set=w, seed=s) for w in ("nominal", "penalize-hip") for s in (0, 1, 2)]
    other = [make_result(weight_set="3,1,5", seed=0)]
    cells = {c.condition: c for c in summarise(paper + other)}
    assert cells["ideal"].cases == 6 and cells["ideal"].weight_error_ci is not None
    assert cells["ideal, other weight sets"].cases == 1


def test_the_header_says_when_seeds_repeat_the_demonstration(make_result):
    """Identical demonstrations across seeds are stated (intervals are then points); different ones are not."""
    same = [dataclasses.replace(make_result(seed=s), demo_features={"hip": 0.1, "knee": 0.2}) for s in (0, 1, 2)]
    assert demo_spread(same) == 0.0 and "differ by at most 0 (relative)" in markdown(same)
    other = [dataclasses.replace(r, demo_features={"hip": 0.1 * (1 + r.seed), "knee": 0.2}) for r in same]
    assert demo_spread(other) == pytest.approx(2 / 3) and "differ by at most" not in markdown(other)


def test_demonstrations_of_two_models_with_one_weight_set_name_are_not_compared(make_result):
    """The walker's and the compass walker's "nominal" weigh different features: each model's
    demonstrations are compared among themselves only (a mix once crashed the leaderboard)."""
    walker = [dataclasses.replace(make_result(seed=s), demo_features={"hip": 0.1, "knee": 0.2}) for s in (0, 1)]
    compass = [dataclasses.replace(r, model="compass", demo_features={"hip": 0.3, "dtau": 0.1}) for r in walker]
    assert demo_spread(walker + compass) == 0.0


def test_a_board_names_its_results_folder_not_where_it_lies(tmp_path, make_result):
    from ioc_bench.cli import main
    from ioc_bench.runner.results import write_result
    from ioc_bench.synthetic.case import CaseSpec

    results = tmp_path / "deep" / "results-x"
    write_result(results, CaseSpec("log-barrier", "nominal", "ideal", 0), make_result())
    assert main(["leaderboard", str(results), "--out", str(tmp_path / "board")]) == 0
    for name in ("README.md", "leaderboard.json"):
        text = (tmp_path / "board" / name).read_text()
        assert "ioc-bench leaderboard results-x" in text and str(tmp_path) not in text


def test_a_board_regenerates_from_its_own_cases_and_new_results_replace_kept_ones(tmp_path, make_result):
    """A board keeps every case (without its history), reads back as a source, and a later
    source's case replaces the kept one: a board regenerated by parts."""
    from ioc_bench.runner.results import board_records, select_sources

    first = tmp_path / "first"
    for seed in range(3):
        for cond in ("ideal", "noise"):
            case = make_result("bilevel", "nominal", cond, seed)
            write_result(first, CaseSpec("bilevel", "nominal", cond, seed), case)
    assert main(["leaderboard", str(first), "--out", str(tmp_path / "board")]) == 0
    board = tmp_path / "board" / "leaderboard.json"
    kept = board_records(board)
    assert len(kept) == 6 and all(r.history == () for r in kept)
    again = tmp_path / "again"
    better = make_result("bilevel", "nominal", "noise", 1, weight_error=0.002)
    write_result(again, CaseSpec("bilevel", "nominal", "noise", 1), better)
    merged = select_sources([board, again])
    assert len(merged) == 6
    (noise1,) = [r for r in merged if r.condition == "noise" and r.seed == 1]
    assert noise1.weight_error == pytest.approx(better.weight_error)
    assert main(["leaderboard", str(board), str(again), "--out", str(tmp_path / "parts")]) == 0
    assert "ioc-bench leaderboard leaderboard.json again" in (tmp_path / "parts" / "README.md").read_text()


def test_a_board_file_that_is_not_a_board_is_refused_in_one_line(tmp_path, capsys):
    bad = tmp_path / "leaderboard.json"
    bad.write_text(json.dumps({"cells": []}))
    with pytest.raises(SystemExit) as exc:
        main(["leaderboard", str(bad), "--out", str(tmp_path / "out")])
    err = capsys.readouterr().err.strip()
    assert exc.value.code == 2
    assert "is not a board: it has no list of cases" in err and len(err.splitlines()) == 1
    bad.write_text(json.dumps({"cases": [], "human_cases": 3}))
    with pytest.raises(SystemExit):
        main(["leaderboard", str(bad), "--out", str(tmp_path / "out")])
    assert "its human_cases is not a list" in capsys.readouterr().err


def test_a_board_writes_its_cases_as_csv_and_a_page_with_its_figures(results_dir, tmp_path):
    import csv

    from ioc_bench.synthetic.board import CSV_COLUMNS

    out = tmp_path / "board"
    (out / "figures").mkdir(parents=True)
    (out / "figures" / "robustness.png").write_bytes(b"\x89PNG\r\n\x1a\nrobust")
    (out / "figures" / "figure6.png").write_bytes(b"\x89PNG\r\n\x1a\nsix")
    write_leaderboard(load_results(results_dir), out)
    rows = list(csv.DictReader((out / "cases.csv").open()))
    assert tuple(rows[0]) == CSV_COLUMNS and len(rows) == 13  # 12 cases and the failed one
    (failed,) = [r for r in rows if r["status"] == "failed"]
    assert failed["weight_error"] == "" and "boom" in failed["reason"]
    md = (out / "README.md").read_text()
    assert "![Weight error against perturbation severity](figures/robustness.png)" in md
    assert "[figure6](figures/figure6.png)" in md
    assert "| algorithm | model | ideal | noise | mass |" in md  # the grid: one column per condition
    page = (out / "leaderboard.html").read_text()
    assert "data:image/png;base64," in page and "<table" in page
