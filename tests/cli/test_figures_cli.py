"""``ioc-bench figures``: files written, JSON report, one-line errors with exit code 2."""

from __future__ import annotations

import json

import pytest
from synthetic import synthetic_result

from ioc_bench.cli import main
from ioc_bench.runner.results import write_result
from ioc_bench.synthetic.case import CaseResult, CaseSpec


def _case(algorithm: str, weight_set: str, condition: str, status: str = "converged") -> CaseResult:
    return synthetic_result(algorithm, weight_set, condition, failed=status == "failed")


@pytest.fixture(scope="module")
def results_dir(tmp_path_factory):
    root = tmp_path_factory.mktemp("results")
    cases = [
        _case("alpha", "nominal", "ideal"),
        _case("alpha", "nominal", "distractor"),
        _case("beta", "nominal", "ideal"),
        _case("beta", "penalize-hip", "distractor"),
        _case("beta", "nominal", "mass", status="failed"),
    ]
    for r in cases:
        write_result(root, CaseSpec(r.algorithm, r.weight_set, r.condition, r.seed), r)
    return root


def _bad_exit(capsys, *argv: str) -> str:
    with pytest.raises(SystemExit) as exc:
        main(list(argv))
    assert exc.value.code == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "Traceback" not in err, err
    return err


def test_json_report_maps_figures_to_written_files(results_dir, tmp_path, capsys):
    out = tmp_path / "figs"
    assert main(["figures", str(results_dir), "--out", str(out), "--algorithm", "beta", "--json"]) == 0
    report = json.loads(capsys.readouterr().out)
    assert set(report) == {"table1", "figure4_beta", "figure5_beta", "figure6"}
    for name, path in report.items():
        assert path.startswith(str(out))
        with open(path, "rb") as f:
            data = f.read()
        assert data.startswith(b"# Table I") if name == "table1" else data[:4] == b"\x89PNG" and len(data) > 10_000


def test_human_report_lists_the_files(results_dir, tmp_path, capsys, monkeypatch):
    from ioc_bench.viz import figures

    # the drawing itself is tested in tests/viz; here only what the command prints
    monkeypatch.setattr(figures.FigurePlan, "draw", lambda plan: {"table1": plan.out / "table1.md"})
    assert main(["figures", str(results_dir), "--out", str(tmp_path)]) == 0
    assert capsys.readouterr().out.split() == ["table1", str(tmp_path / "table1.md")]


def test_missing_results_dir_exits_2(tmp_path, capsys):
    err = _bad_exit(capsys, "figures", str(tmp_path / "nope"), "--out", str(tmp_path / "out"))
    assert "not found" in err
    assert not (tmp_path / "out").exists()


def test_empty_results_dir_exits_2(tmp_path, capsys):
    (tmp_path / "empty").mkdir()
    err = _bad_exit(capsys, "figures", str(tmp_path / "empty"), "--out", str(tmp_path / "out"))
    assert "no case results" in err


def test_unknown_algorithm_exits_2_listing_those_present(results_dir, tmp_path, capsys):
    err = _bad_exit(capsys, "figures", str(results_dir), "--out", str(tmp_path), "--algorithm", "gamma")
    assert "gamma" in err and "alpha, beta" in err
    assert not any(tmp_path.iterdir())


def test_unreadable_result_file_exits_2(tmp_path, capsys):
    (tmp_path / "res" / "alpha").mkdir(parents=True)
    (tmp_path / "res" / "alpha" / "nominal__ideal__seed0.json").write_text("{not json")
    err = _bad_exit(capsys, "figures", str(tmp_path / "res"), "--out", str(tmp_path / "out"))
    assert "nominal__ideal__seed0.json" in err


def test_json_files_not_named_like_results_are_not_read_but_named(tmp_path, capsys):
    (tmp_path / "res" / "alpha").mkdir(parents=True)
    (tmp_path / "res" / "alpha" / "x.json").write_text("{not json")
    err = _bad_exit(capsys, "figures", str(tmp_path / "res"), "--out", str(tmp_path / "out"))
    assert "no case results" in err and "alpha/x.json" in err
