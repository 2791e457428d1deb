"""``ioc-bench compare A B``: the text report, --json, exit codes; on made-up result folders (no solve)."""

from __future__ import annotations

import json

import pytest
from synthetic import grid_errors, write_run

from ioc_bench.cli import main
from ioc_bench.cli.compare import compare_folders


def _run(capsys, *argv) -> tuple[int, str, str]:
    code = main([str(a) for a in argv])
    out = capsys.readouterr()
    return code, out.out, out.err


@pytest.fixture
def runs(tmp_path):
    """Folders A, a copy of A, and B: bilevel's weight errors 0.02 higher, one log-barrier case failed."""
    base = grid_errors()
    higher = {case: e + (0.02 if case[0] == "bilevel" else 0.0) for case, e in base.items()}
    failed = {("log-barrier", "noise", "nominal", 1)}
    return (
        write_run(tmp_path / "a", base),
        write_run(tmp_path / "same", base),
        write_run(tmp_path / "b", higher, failed=failed),
    )


def test_identical_folders_print_no_difference_and_exit_0(runs, capsys):
    a, same, _ = runs
    code, out, err = _run(capsys, "compare", a, same)
    assert code == 0 and err == ""
    rows = [line for line in out.splitlines() if line.startswith("walker ")]
    assert len(rows) == 4 and all("no difference" in row and "+0.0000 [+0.0000, +0.0000]" in row for row in rows)
    assert "cells that differ: none" in out and "status changes: none" in out and "only in" not in out


def test_a_worse_algorithm_and_a_changed_status_are_shown(runs, capsys):
    a, _, b = runs
    code, out, _ = _run(capsys, "compare", a, b)
    assert code == 0
    rows = {tuple(line.split()[1:3]): line for line in out.splitlines() if line.startswith("walker ")}
    assert "worse" in rows[("bilevel", "ideal")] and "worse" in rows[("bilevel", "noise")]
    assert "no difference" in rows[("log-barrier", "ideal")] and "no difference" in rows[("log-barrier", "noise")]
    assert "0 -> 1" in rows[("log-barrier", "noise")]  # failures A -> B
    assert "cells that differ (2): walker / bilevel / ideal (worse), walker / bilevel / noise (worse)" in out
    assert "status changes (1):" in out
    assert "now fails: log-barrier/nominal__noise__seed1: converged -> failed (RuntimeError: synthetic failure)" in out


def test_json_holds_the_same_verdicts(runs, capsys):
    a, _, b = runs
    code, out, _ = _run(capsys, "compare", a, b, "--json", "--level", "0.9")
    data = json.loads(out)
    assert code == 0 and data["level"] == 0.9 and data["headline"] == "weight_error"
    expected = {(c.label, c.condition): c.verdict for c in compare_folders(a, b, 0.9).cells}
    assert {(c["label"], c["condition"]): c["verdict"] for c in data["cells"]} == expected
    assert data["verdicts"] == {"better": 0, "worse": 2, "no difference": 2, "n/a": 0}
    [change] = data["status_changes"]
    assert change["case"] == "log-barrier/nominal__noise__seed1" and change["kind"] == "now fails"
    bilevel = next(c for c in data["cells"] if c["label"] == "bilevel" and c["condition"] == "ideal")
    weight = bilevel["differences"]["weight_error"]
    assert weight["verdict"] == "worse" and weight["difference"] == pytest.approx(0.02) and weight["pairs"] == 6
    assert bilevel["differences"]["transfer_error"]["difference"] is None  # NaN as null: no transfer here


def test_identical_folders_in_json(runs, capsys):
    a, same, _ = runs
    data = json.loads(_run(capsys, "compare", a, same, "--json")[1])
    assert {c["verdict"] for c in data["cells"]} == {"no difference"} and data["status_changes"] == []
    assert all(d["difference"] in (0, None) for c in data["cells"] for d in c["differences"].values())


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["{a}", "{tmp}/missing"], "results directory not found"),
        (["{a}", "{empty}"], "no case results in"),
        (["{a}", "{other}"], "have no case in common"),
        (["{a}", "{corrupt}"], "is not a case result: not JSON"),
        (["{a}/bilevel/nominal__ideal__seed0.json", "{a}"], "is a file: compare reads two results folders"),
        (["{a}", "{a}", "--level", "95"], "must be a number between 0 and 1"),
    ],
)
def test_bad_input_exits_2_with_one_line(runs, tmp_path, capsys, argv, message):
    a = runs[0]
    (tmp_path / "empty").mkdir()
    write_run(tmp_path / "other", {("inverse-kkt", "ideal", "nominal", 0): 0.01})
    corrupt = write_run(tmp_path / "corrupt", {("bilevel", "ideal", "nominal", 0): 0.01})
    (corrupt / "bilevel" / "nominal__ideal__seed0.json").write_text("{not json")
    paths = {"{a}": a, "{tmp}": tmp_path, "{empty}": tmp_path / "empty", "{other}": tmp_path / "other"}
    paths["{corrupt}"] = corrupt
    resolved = []
    for arg in argv:
        for token, path in paths.items():
            arg = arg.replace(token, str(path))
        resolved.append(arg)
    with pytest.raises(SystemExit) as exc:
        main(["compare", *resolved])
    err = capsys.readouterr().err
    assert exc.value.code == 2 and len(err.splitlines()) == 1 and "Traceback" not in err
    assert err.startswith("ioc-bench compare: error: ") and message in err, err
