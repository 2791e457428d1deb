"""The board's ranking: the paper's conditions counted once each, complete rows first."""

from __future__ import annotations

import pytest
from synthetic import synthetic_result

from ioc_bench.synthetic.board import row_condition, summarise
from ioc_bench.synthetic.ranking import RANKED_CONDITIONS, grid_lines, paper_lines, rank, ranking_lines


def _cases(algorithm: str, errors: dict[str, float], seeds=(0, 1, 2), weight_sets=("nominal", "penalize-knee")):
    return [
        synthetic_result(algorithm, ws, cond, seed, weight_error=error)
        for cond, error in errors.items()
        for ws in weight_sets
        for seed in seeds
    ]


def _rank(results):
    return rank(results, row_condition)


def test_each_condition_counts_once_however_many_cases_it_has() -> None:
    # "a" is 0.01 everywhere but 0.5 in one condition run with a single weight set
    errors = dict.fromkeys(RANKED_CONDITIONS, 0.01)
    a = _cases("a", {c: e for c, e in errors.items() if c != "speed"}) + _cases(
        "a", {"speed": 0.5}, weight_sets=("nominal",)
    )
    b = _cases("b", dict.fromkeys(RANKED_CONDITIONS, 0.05))
    first, second = _rank(a + b)
    assert (first.label, second.label) == ("b", "a")  # a's mean is (5 * 0.01 + 0.5) / 6 ~ 0.092
    assert second.weight_error == pytest.approx((5 * 0.01 + 0.5) / 6, rel=0.05)
    assert second.hardest == "speed" and second.complete


def test_rows_missing_a_paper_condition_rank_after_complete_ones_and_say_so() -> None:
    full = _cases("full", dict.fromkeys(RANKED_CONDITIONS, 0.2))
    partial = _cases("partial", {"ideal": 0.0001})
    rows = _rank(full + partial)
    assert [r.label for r in rows] == ["full", "partial"]
    lines = ranking_lines(rows, lambda x: f"{x:.4f}")
    assert lines[2].startswith("| 1 | full |") and "(1 of 6 conditions)" in lines[3] and lines[3].startswith("| - |")


def test_the_interval_needs_three_seeds_per_weight_set_and_holds_the_mean() -> None:
    varied = [
        synthetic_result("a", ws, cond, seed, weight_error=0.01 * (1 + seed))
        for cond in RANKED_CONDITIONS
        for ws in ("nominal", "penalize-hip")
        for seed in (0, 1, 2)
    ]
    (row,) = _rank(varied)
    low, high = row.interval
    assert low < row.weight_error < high
    (few,) = _rank(_cases("a", dict.fromkeys(RANKED_CONDITIONS, 0.01), seeds=(0, 1)))
    assert few.interval is None


def test_the_grid_and_the_paper_table_show_each_algorithms_cells() -> None:
    results = _cases("a", {"ideal": 0.001, "noise": 0.2}) + _cases("b", {"ideal": 0.3})
    cells = summarise(results)
    grid = grid_lines(cells, lambda x: f"{x:.3f}")
    assert grid[0] == "| algorithm | model | ideal | noise |"
    assert grid[3] == "| b | walker | 0.300 | - |"
    paper = paper_lines(cells, lambda x: f"{x:.3f}")
    assert paper[0] == "| condition | the paper | a | b |"
    noise = next(line for line in paper if line.startswith("| noise |"))
    assert "**0.200**" in noise and noise.endswith("| - |")  # a's hardest; b did not run it
