"""Table I and Figures 4-6 from synthetic case results (no optimization runs here)."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
from synthetic import estimate_with_error

from ioc_bench.features import ALL_FEATURES, COST_FEATURES
from ioc_bench.runner.results import write_result
from ioc_bench.synthetic.case import CaseResult, CaseSpec
from ioc_bench.synthetic.results import parse_result
from ioc_bench.viz import figures
from ioc_bench.weights import WEIGHT_SETS, parse_weights

#: Demonstration features where each penalised feature is lowest under its own set.
GOOD_DEMOS = {
    "nominal": {"hip": 5e-4, "knee": 3e-4, "dtau": 7e-5},
    "penalize-hip": {"hip": 1e-4, "knee": 1e-3, "dtau": 1.6e-4},
    "penalize-knee": {"hip": 1.2e-3, "knee": 2e-5, "dtau": 8e-5},
    "penalize-dtau": {"hip": 7e-4, "knee": 3.6e-4, "dtau": 1.3e-5},
}
#: The same, except that knee is lowest under penalize-hip (the pattern breaks for knee).
BAD_DEMOS = GOOD_DEMOS | {"penalize-hip": {"hip": 1e-4, "knee": 1e-5, "dtau": 1.6e-4}}


def make_case(
    algorithm: str,
    weight_set: str,
    condition: str,
    seed: int = 0,
    status: str = "converged",
    weight_error: float = 0.01,
    trajectory_error: float = 1e-5,
    demos: dict = GOOD_DEMOS,
) -> CaseResult:
    """A plausible result: four iterations moving from uniform weights to the truth."""
    features = ALL_FEATURES if condition == "distractor" else COST_FEATURES
    true = parse_weights(weight_set, features)
    start = np.ones(len(features)) / math.sqrt(len(features))
    history = tuple(
        {
            "weights": list((1 - t) * start + t * true),
            "trajectory_error": 10.0 ** -(3 + 2 * t),
            "cost_gap": -0.1,
            "solve_status": "Solve_Succeeded",
            "extra": {},
        }
        for t in np.linspace(0, 1, 4)
    )
    failed = status == "failed"
    estimate = estimate_with_error(true, weight_error)
    return CaseResult(
        algorithm=algorithm,
        weight_set=weight_set,
        condition=condition,
        seed=seed,
        features=features,
        status=status,
        reason="RuntimeError: synthetic failure" if failed else "",
        weights=(math.nan,) * len(features) if failed else estimate,
        true_weights=tuple(true),
        weight_error=math.nan if failed else float(np.mean(np.abs(np.array(estimate) - true))),
        trajectory_error=math.nan if failed else trajectory_error,
        n_solves=0 if failed else 4,
        wall_time=1.0,
        history=() if failed else history,
        chosen_iteration=None if failed else 3,
        found_trajectory_error=None if failed else history[3]["trajectory_error"],
        demo_features=dict(demos[weight_set]) | {"torso": 5e-3, "steplen": 7e-3, "footheight": 4e-2},
        demo_speed=0.34 if condition == "ideal-fast" else 0.27,
    )


def synthetic_results() -> list[CaseResult]:
    """Two algorithms over a few conditions, with a failed case and 6-feature distractor cases."""
    return [
        make_case("alpha", "nominal", "ideal", seed=1, weight_error=0.5),
        make_case("alpha", "nominal", "ideal", seed=0, weight_error=0.01),
        make_case("alpha", "penalize-hip", "ideal", weight_error=0.03),
        make_case("alpha", "nominal", "distractor", weight_error=0.2, status="max_iterations"),
        make_case("alpha", "penalize-hip", "mass", status="failed"),
        make_case("alpha", "penalize-hip", "noise", weight_error=0.05, trajectory_error=1e-2),
        make_case("beta", "nominal", "ideal", weight_error=0.02),
        make_case("beta", "penalize-knee", "distractor", weight_error=0.1),
    ]


@pytest.fixture(scope="module")
def results_dir(tmp_path_factory):
    root = tmp_path_factory.mktemp("results")
    for r in synthetic_results():
        write_result(root, CaseSpec(r.algorithm, r.weight_set, r.condition, r.seed), r)
    return root


@pytest.fixture(scope="module")
def written(results_dir, tmp_path_factory):
    return figures.make_figures(results_dir, tmp_path_factory.mktemp("figures"))


# --------------------------------------------------------------------------- make_figures


def test_every_figure_is_written_and_non_trivial(written):
    assert set(written) == {
        "table1",
        "figure4_alpha",
        "figure4_beta",
        "figure5_alpha",
        "figure5_beta",
        "figure6",
    }
    for name, path in written.items():
        assert path.is_file(), name
        if path.suffix == ".png":
            assert path.read_bytes()[:4] == b"\x89PNG"
            assert path.stat().st_size > 20_000, name
    assert "phi_hip" in written["table1"].read_text()


def test_algorithm_filter_and_unknown_algorithm(results_dir, tmp_path):
    assert {r.algorithm for r in figures.select_results(results_dir, ["beta"])} == {"beta"}
    assert len(figures.select_results(results_dir)) == len(synthetic_results())
    with pytest.raises(ValueError, match=r"gamma.*present: alpha, beta"):
        figures.make_figures(results_dir, tmp_path, algorithms=["beta", "gamma"])


def test_missing_or_empty_results_dir(tmp_path):
    with pytest.raises(ValueError, match="not found"):
        figures.make_figures(tmp_path / "nope", tmp_path / "out")
    (tmp_path / "empty").mkdir()
    with pytest.raises(ValueError, match="no case results"):
        figures.make_figures(tmp_path / "empty", tmp_path / "out")


# --------------------------------------------------------------------------- Table I


def _rows(markdown: str, speed: str) -> dict[str, list[str]]:
    """Cells of each feature row in the table under the heading of ``speed``."""
    section = markdown.split(f"## Speed {speed}")[1].split("## Speed")[0]
    rows = [line.strip("|").split("|") for line in section.splitlines() if line.startswith("| phi_")]
    return {cells[0].strip(): [c.strip() for c in cells[1:]] for cells in rows}


def _table1_cases(condition: str, demos: dict) -> list[CaseResult]:
    return [make_case("alpha", ws, condition, demos=demos) for ws in WEIGHT_SETS]


def test_table1_bolds_row_minima_and_checks_the_pattern():
    md = figures.table1_markdown(_table1_cases("ideal", GOOD_DEMOS) + _table1_cases("ideal-fast", BAD_DEMOS))
    good, bad = _rows(md, "0.27"), _rows(md, "0.34")
    bold_column = {f: [i for i, c in enumerate(cells[:4]) if c.startswith("**")] for f, cells in good.items()}
    assert bold_column == {"phi_hip": [1], "phi_knee": [2], "phi_dtau": [3]}
    assert [cells[4] for cells in good.values()] == ["yes", "yes", "yes"]
    assert bad["phi_knee"][1].startswith("**") and not bad["phi_knee"][2].startswith("**")
    assert bad["phi_knee"][4] == "NO (lowest: penalize-hip)"
    assert bad["phi_hip"][4] == "yes" and bad["phi_dtau"][4] == "yes"
    assert "holds: 3 of 3" in md and "DOES NOT hold: 2 of 3" in md


def test_table1_skips_absent_sets_and_says_when_empty():
    cases = [make_case("alpha", ws, "ideal") for ws in ("nominal", "penalize-hip", "penalize-dtau")]
    cases.append(make_case("alpha", "3,1,5", "ideal", demos={"3,1,5": GOOD_DEMOS["nominal"]}))
    md = figures.table1_markdown(cases)
    assert "penalize-knee |" not in md and "3,1,5" not in md and "0.34" not in md
    assert "n/a (penalize-knee absent)" in md and "absent from the results: penalize-knee" in md
    empty = figures.table1_markdown([make_case("alpha", "nominal", "noise")])
    assert "No Table I available" in empty and "|" not in empty


def test_table1_ignores_failed_demonstrations_but_not_failed_algorithms():
    broken = make_case("alpha", "nominal", "ideal", status="failed", demos=BAD_DEMOS)
    broken = parse_result(broken.to_dict() | {"demo_features": {}})  # as run_case records it
    algo_failed = make_case("beta", "penalize-hip", "ideal", status="failed")
    md = figures.table1_markdown([broken, algo_failed])
    assert "nominal |" not in md and "penalize-hip" in md


# --------------------------------------------------------------------------- Figures 4-6


@pytest.fixture
def drawn(monkeypatch):
    """Records the cases each convergence panel draws."""
    cases: list[CaseResult] = []
    real = figures.draw_convergence

    def record(ax, result, legend=True):
        cases.append(result)
        real(ax, result, legend)

    monkeypatch.setattr(figures, "draw_convergence", record)
    return cases


def test_figure4_draws_the_lowest_seed_of_each_ideal_case(drawn, tmp_path):
    figures.plot_figure4(synthetic_results(), "alpha", tmp_path / "f4.png")
    assert [(c.weight_set, c.seed) for c in drawn] == [("nominal", 0), ("penalize-hip", 0)]
    with pytest.raises(ValueError, match="no ideal"):
        figures.plot_figure4([make_case("gamma", "nominal", "noise")], "gamma", tmp_path / "x.png")


def test_figure5_draws_the_imperfect_cases_with_six_distractor_weights(drawn, tmp_path):
    figures.plot_figure5(synthetic_results(), "alpha", tmp_path / "f5.png")
    assert [(c.condition, c.weight_set) for c in drawn] == [("distractor", "nominal"), ("noise", "penalize-hip")]
    assert len(drawn[0].features) == 6 and len(drawn[0].history[0]["weights"]) == 6
    assert (tmp_path / "f5.png").stat().st_size > 20_000  # the failed mass case is a note, not a crash


@pytest.fixture
def saved(monkeypatch):
    """Keeps each figure passed to ``save_figure`` for inspection."""
    figs = []
    real = figures.save_figure

    def keep(fig, path):
        figs.append(fig)
        return real(fig, path)

    monkeypatch.setattr(figures, "save_figure", keep)
    return figs


def test_figure6_means_exclude_failed_cases_and_count_them(saved, tmp_path):
    results = synthetic_results()
    results.append(make_case("alpha", "penalize-knee", "mass", weight_error=0.07))
    figures.plot_figure6(results, tmp_path / "f6.png")
    fig = saved[0]
    weight_ax, traj_ax = fig.axes[:2]
    heights = sorted(round(p.get_height(), 6) for p in weight_ax.patches)
    # alpha: ideal mean(0.5, 0.01, 0.03), distractor 0.2, mass 0.07 (failed one left out), noise 0.05;
    # beta: ideal 0.02, distractor 0.1
    assert heights == sorted([0.18, 0.2, 0.07, 0.05, 0.02, 0.1])
    assert traj_ax.get_yscale() == "log"
    notes = " ".join(t.get_text() for t in fig.texts)
    assert "1 failed case(s) excluded" in notes and "alpha / mass: 1" in notes


def test_figure6_marks_a_condition_where_every_case_failed(saved, tmp_path):
    results = [make_case("alpha", "nominal", "ideal"), make_case("alpha", "nominal", "mass", status="failed")]
    figures.plot_figure6(results, tmp_path / "f6.png")
    assert any(t.get_text() == "all failed" for t in saved[0].axes[0].texts)


def test_two_configs_of_one_algorithm_are_drawn_apart(tmp_path):
    quick = {"n_random": 1, "max_iterations": 2}
    cases = [
        (CaseSpec("log-barrier", "nominal", "ideal", 0), make_case("log-barrier", "nominal", "ideal")),
        (
            CaseSpec("log-barrier", "nominal", "ideal", 0, quick),
            dataclasses.replace(make_case("log-barrier", "nominal", "ideal", weight_error=0.5), config=quick),
        ),
    ]
    for spec, case in cases:
        write_result(tmp_path / "res", spec, case)
    written = figures.make_figures(tmp_path / "res", tmp_path / "figs")
    assert {"figure4_log-barrier", "figure4_log-barrier__cfg05519c9f"} <= set(written)


def test_output_names_come_from_checked_identifiers_only(tmp_path):
    """A result whose algorithm field is ``x/../../ESCAPED`` cannot make figures write a PNG outside --out."""
    good = figures.output_names(synthetic_results())
    assert good["figure4_alpha"] == "figure4_alpha.png" and "/" not in "".join(good.values())
    for bad in ("x/../../ESCAPED", "../x", ".hidden", "a b"):
        escaping = dataclasses.replace(make_case("alpha", "nominal", "ideal"), algorithm=bad)
        with pytest.raises(ValueError, match="unsafe algorithm name"):
            figures.output_names([escaping])
    assert not any(tmp_path.iterdir())


def test_every_output_is_checked_before_drawing(results_dir, tmp_path):
    (tmp_path / "figure6.png").mkdir()
    with pytest.raises(ValueError, match=r"figure6\.png is a directory"):
        figures.make_figures(results_dir, tmp_path)
    assert [p.name for p in tmp_path.iterdir()] == ["figure6.png"]  # not even table1.md was written
    with pytest.raises(ValueError, match="empty string"):
        figures.make_figures(results_dir, "")
