"""studies/cost_basis_floor.py without solving: its lattice and solve counts, resuming, and
``--table`` on a hand-written file."""

from __future__ import annotations

import importlib.util
import json
import sys
from pathlib import Path

import pytest

PATH = Path(__file__).resolve().parents[1] / "studies" / "cost_basis_floor.py"


@pytest.fixture(scope="module")
def study():
    spec = importlib.util.spec_from_file_location("cost_basis_floor_under_test", PATH)
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module
    spec.loader.exec_module(module)
    yield module
    sys.modules.pop(spec.name, None)


def test_the_cells_bases_and_lattices(study):
    assert study.basis_features("walker", "effort") == ("hip", "knee", "dtau")
    assert study.basis_features("walker", "rich") == ("hip", "knee", "dtau", "work", "collision")
    assert study.basis_features("ankle", "effort") == ("hip", "knee", "ankle", "dtau")
    assert study.basis_features("ankle", "rich") == ("hip", "knee", "ankle", "dtau", "work", "collision")
    counts = {(m, b): len(study.lattice(len(study.basis_features(m, b)), 2)) for m in study.MODELS for b in study.BASES}
    assert counts == {("walker", "effort"): 6, ("walker", "rich"): 15, ("ankle", "effort"): 10, ("ankle", "rich"): 21}
    for n in range(1, 7):
        for d in range(1, 5):
            points = study.lattice(n, d)
            assert len(points) == len(set(points)) == study.lattice_size(n, d)
            assert all(sum(p) == d and min(p) >= 0 for p in points)
    # the rich lattice holds every effort direction (work and collision at 0)
    rich = set(study.lattice(5, 2))
    assert all((*p, 0, 0) in rich for p in study.lattice(3, 2))
    assert study.direction_label(("hip", "knee", "dtau"), (1, 0, 1)) == "hip:1 dtau:1"


def test_the_plan_counts_the_solves(study, tmp_path):
    args = study.parse_args(["--out", str(tmp_path / "none.jsonl")])
    assert (args.divisions, args.starts) == (2, 8)
    units = study.pending(args, [])
    assert len(units) == 3 * 4 * 2 * 2
    assert study.unit_solves("walker", "effort", 2, 8) == 6 * 8 + 2
    assert study.unit_solves("ankle", "rich", 2, 8) == 21 * 8 + 2
    text = study.plan(args, units)
    assert "| all | | | 48 | 5088 |" in text
    one = study.parse_args(["--out", "x", "--models", "walker", "--bases", "rich", "--subjects", "WBDS01"])
    assert study.pending(one, []) == [("WBDS01", t, "walker", "rich") for t in study.TRIALS]


def test_bad_choices_are_refused(study):
    for argv in (["--models", "compass"], ["--bases", "effort,fancy"], ["--trials", "T07"], ["--starts", "0"]):
        with pytest.raises(SystemExit):
            study.parse_args(argv)


def test_the_verdict(study):
    assert study.verdict(0.5, 0.01) == "rejected"
    assert study.verdict(0.05, 0.01) == "not rejected"
    assert study.verdict(None, 0.01) == study.verdict(0.5, None) == study.verdict(float("nan"), 0.1) == "n/a"


def _record(subject, trial, model, basis, rmse, ratio, verdict, divisions=2, starts=8):
    return {
        "subject": subject,
        "trial": trial,
        "model": model,
        "basis": basis,
        "divisions": divisions,
        "starts": starts,
        "seed": 0,
        "person_step_length": 0.6,
        "n_directions": 6 if basis == "effort" else 15,
        "features": ["hip", "knee", "dtau", *(["work", "collision"] if basis == "rich" else [])],
        "directions": [
            {"success": True, "label": "hip:1 dtau:1", "lattice": [1, 0, 1, 0, 0], "rmse_deg": rmse},
            {"success": False, "label": "knee:2", "lattice": [0, 2, 0, 0, 0], "rmse_deg": None},
        ],
        "best": {"label": "hip:1 dtau:1", "rmse_deg": rmse, "step_length": 0.55, "step_length_error": 0.087},
        "projection": {"rmse_deg": 0.8},
        "rejection": {
            "verdict": verdict,
            "ratio": ratio,
            "person": {"relative_residual": 0.2},
            "synthetic_projection": {"relative_residual": 0.2 / ratio if ratio else None},
        },
        "solves": 50,
        "wall_time": 75.0,
    }


FIXTURE = [
    _record("WBDS01", "T03", "walker", "effort", 8.0, 40.0, "rejected"),
    _record("WBDS01", "T04", "walker", "effort", 6.0, 20.0, "rejected"),
    _record("WBDS01", "T03", "walker", "rich", 5.0, 4.0, "not rejected"),
    _record("WBDS01", "T04", "walker", "rich", None, None, "n/a"),
    _record("WBDS01", "T03", "walker", "effort", 1.0, 1.0, "not rejected", divisions=3),  # other settings
]


def test_the_table_of_a_hand_written_file(study, tmp_path, capsys):
    path = tmp_path / "floor.jsonl"
    path.write_text("\n".join(json.dumps(r) for r in FIXTURE) + "\n{not json\n")
    study.main(["--out", str(path), "--table"])
    out = capsys.readouterr().out
    assert "4 units (1 other units with other settings not shown)" in out
    assert "| walker | 7.00 (2) | 5.00 (2) |" in out  # medians of the best RMSE per cell (trials)
    assert "| ankle | - (0) | - (0) |" in out
    assert "| walker | effort | 6 | 2 | 7.00 (6.00-8.00) | 0.087 | 0.80 | 2 / 2 (0) | 30 |" in out
    assert "| walker | rich | 15 | 2 | 5.00 (5.00-5.00) | 0.087 | 0.80 | 0 / 1 (1) | 4 |" in out
    assert (
        "| WBDS01 | T03 | walker | effort | hip:1 dtau:1 | 8.00 | 0.550 / 0.600 | 0.087 | 0.80 | 0.2 / 0.005 |" in out
    )
    assert "| WBDS01 | T04 | walker | rich | hip:1 dtau:1 | - |" in out


def test_records_append_and_resume(study, tmp_path):
    path = tmp_path / "floor.jsonl"
    record = _record("WBDS02", "T05", "ankle", "rich", float("nan"), None, "n/a")
    study.append_record(path, record)
    study.append_record(path, _record("WBDS02", "T06", "ankle", "rich", 3.0, 2.0, "not rejected"))
    back = study.read_records(path)
    assert len(back) == 2 and back[0]["best"]["rmse_deg"] is None  # NaN is written as null
    args = study.parse_args(["--out", str(path), "--subjects", "WBDS02", "--models", "ankle", "--bases", "rich"])
    assert study.pending(args, back) == [("WBDS02", "T03", "ankle", "rich"), ("WBDS02", "T04", "ankle", "rich")]
    more = study.parse_args(["--out", str(path), "--subjects", "WBDS02", "--models", "ankle", "--starts", "9"])
    assert len(study.pending(more, back)) == 8  # other settings are other units


@pytest.mark.filterwarnings("ignore::RuntimeWarning")  # the KKT fit at points no solver has seen
def test_units_run_end_to_end_with_a_stand_in_solver(study, tmp_path, monkeypatch):
    """Every step of a unit but IPOPT: each solve returns its start, called a success."""
    from types import SimpleNamespace

    import numpy as np

    from ioc_bench.human import WbdsData, human_step
    from ioc_bench.trajopt.forward_problem import ForwardProblem
    from ioc_bench.trajopt.solution import SolveResult, SolverReport

    def stand_in(self, request):
        x = np.clip(request.start.x, *self.bounds(request.params, request.task)[:2])
        report = SolverReport("Solve_Succeeded", True, 0.0, 0.0, 1, 0.001, float(np.sum(request.weights)))
        return SolveResult(self.trajectory(x, request.params), report, x, np.zeros_like(x), np.zeros(self.n_g))

    monkeypatch.setattr(ForwardProblem, "solve", stand_in)
    path = tmp_path / "floor.jsonl"
    args = study.parse_args(["--out", str(path), "--divisions", "1", "--starts", "2"])
    trial = WbdsData().trial("WBDS01", "T05")
    step = human_step(trial, n_intervals=4)  # small problems: they build in about a second
    ctx = SimpleNamespace(subject="WBDS01", trial_code="T05", trial=trial, step=step)
    for model in study.MODELS:
        projection = study.person_projection(ctx, model)
        for basis in study.BASES:
            record = study.measure_unit(ctx, model, basis, projection, args, sys.stderr)
            study.append_record(path, record)
            n = len(study.basis_features(model, basis))
            assert record["n_directions"] == len(record["directions"]) == n
            assert record["solves"] == n * 2 + 1  # the directions' starts and the synthetic projection
            assert record["best"]["rmse_deg"] is not None and record["projection"]["ok"]
            assert set(record["rejection"]) >= {"person", "optimum", "synthetic_projection", "verdict", "ratio"}
            assert record["rejection"]["person"]["weights"].keys() == set(study.basis_features(model, basis))
    records = study.read_records(path)
    assert [(r["model"], r["basis"]) for r in records] == [(m, b) for m in study.MODELS for b in study.BASES]
    assert study.pending(study.parse_args(["--out", str(path), "--subjects", "WBDS01", "--trials", "T05",
                                           "--divisions", "1", "--starts", "2"]), records) == []  # fmt: skip
    assert "| WBDS01 | T05 | ankle | rich |" in study.table(records, 1, 2, 0)


def _rich(subject, trial, model, rmses):
    """A rich unit whose directions are ``label -> rmse`` (None: the direction failed)."""
    features = ["hip", "knee", "dtau", "work", "collision"]
    if model == "ankle":
        features.insert(2, "ankle")
    directions = []
    for label, rmse in rmses.items():
        lattice = [dict(p.split(":") for p in label.split()).get(f, 0) for f in features]
        directions.append({"label": label, "lattice": [int(k) for k in lattice], "success": rmse is not None,
                           "rmse_deg": rmse})  # fmt: skip
    ok = {k: v for k, v in rmses.items() if v is not None}
    best = min(ok, key=ok.get)
    return {"subject": subject, "trial": trial, "model": model, "basis": "rich", "features": features,
            "directions": directions, "best": {"rmse_deg": ok[best], "label": best}}  # fmt: skip


def test_the_effort_floor_inside_a_rich_unit(study):
    """A rich unit's effort directions are those weighing no work or collision; a failed one is skipped."""
    rich = _rich("WBDS01", "T05", "ankle", {"hip:1 knee:1": 12.0, "ankle:2": None, "ankle:1 dtau:1": 11.0,
                                            "knee:1 work:1": 9.0, "collision:2": 8.0})  # fmt: skip
    assert study.effort_floor_of_rich(rich) == (11.0, "ankle:1 dtau:1")
    assert study.effort_floor_of_rich(_rich("WBDS01", "T05", "walker", {"work:2": 7.0})) == (None, None)


def test_the_paired_table_compares_the_cells_on_the_same_trials(study):
    records = [
        _rich("WBDS01", "T05", "walker", {"hip:1 knee:1": 15.0, "work:2": 11.0}),
        {**_record("WBDS01", "T05", "walker", "effort", 15.0, 1.0, "n/a"), "features": ["hip", "knee", "dtau"]},
        _rich("WBDS01", "T05", "ankle", {"hip:1 knee:1": 10.0, "collision:2": 9.0}),
        _rich("WBDS03", "T05", "walker", {"hip:1 knee:1": 13.0, "work:2": 12.0}),  # no ankle unit: not in the medians
    ]
    lines = study.paired_table(records)
    assert "| WBDS01 | T05 | walker | 15.00 | 15.00 | 11.00 |" in lines
    assert "| WBDS01 | T05 | ankle | - | 10.00 | 9.00 |" in lines
    assert "| WBDS03 | T05 | ankle |" not in "\n".join(lines)
    assert any(line.startswith("Medians over the 1 trial(s)") and "(WBDS01 T05)" in line for line in lines)
    assert "| walker | 15.00 | 11.00 |" in lines and "| ankle | 10.00 | 9.00 |" in lines
    assert study.paired_table([records[1]]) == []  # no rich unit, no table
