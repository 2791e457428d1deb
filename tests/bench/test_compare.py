"""``compare``: two runs' results paired case by case, a verdict per cell; made-up results, no solve."""

from __future__ import annotations

import math

import numpy as np
import pytest
from synthetic import ALGORITHMS, CONDITIONS, grid_errors, synthetic_result, write_run

from ioc_bench.cli.compare import compare_folders
from ioc_bench.synthetic.compare import BETTER, NA, SAME, WORSE, compare_results, verdict


def cells_by(comparison):
    return {(c.label, c.condition): c for c in comparison.cells}


def test_identical_runs_show_no_difference_anywhere(tmp_path):
    a = write_run(tmp_path / "a", grid_errors())
    b = write_run(tmp_path / "b", grid_errors())
    comparison = compare_folders(a, b)
    assert len(comparison.cells) == len(ALGORITHMS) * len(CONDITIONS) and comparison.paired == len(grid_errors())
    for cell in comparison.cells:
        assert cell.verdict == SAME and cell.paired == 6 and not cell.only_a and not cell.only_b
        for d in cell.differences:
            if d.score.startswith("transfer"):  # made-up results have no transfer score
                assert d.pairs == 0 and d.verdict == NA
            else:
                assert d.pairs == 6 and d.difference == 0 and d.interval == (0.0, 0.0) and d.verdict == SAME
    assert comparison.status_changes == []


def test_higher_weight_errors_of_one_algorithm_make_its_cells_worse_and_only_those(tmp_path):
    base = grid_errors()
    higher = {case: e + (0.02 if case[0] == "bilevel" else 0.0) for case, e in base.items()}
    comparison = compare_folders(write_run(tmp_path / "a", base), write_run(tmp_path / "b", higher))
    cells = cells_by(comparison)
    for cond in CONDITIONS:
        worse = cells[("bilevel", cond)].difference("weight_error")
        assert worse.verdict == WORSE and worse.difference == pytest.approx(0.02, abs=1e-9)
        assert worse.interval[0] > 0 and worse.mean_b > worse.mean_a
        assert cells[("log-barrier", cond)].verdict == SAME
    assert [c.verdict for c in comparison.cells].count(WORSE) == 2
    back = compare_folders(tmp_path / "b", tmp_path / "a")  # the other way round: better
    assert {c.label: c.verdict for c in back.cells if c.condition == "ideal"} == {
        "bilevel": BETTER,
        "log-barrier": SAME,
    }


def test_noisy_differences_whose_interval_holds_zero_are_no_difference():
    base = grid_errors()
    rng = np.random.default_rng(5)
    jitter = {case: max(0.0, e + float(rng.normal(0, 0.005))) for case, e in base.items()}
    comparison = compare_results(_records(base), _records(jitter))
    for cell in comparison.cells:
        d = cell.difference("weight_error")
        low, high = d.interval
        assert (low <= 0 <= high) == (d.verdict == SAME), (cell.name, d)


def test_differences_within_the_tolerance_are_no_difference():
    base = grid_errors()
    tiny = {case: e + 5e-5 for case, e in base.items()}  # below the weight error's 1e-4: solver noise
    comparison = compare_results(_records(base), _records(tiny))
    d = comparison.cells[0].difference("weight_error")
    assert d.interval[0] > 0 and d.verdict == SAME
    assert {c.verdict for c in comparison.cells} == {SAME}


def test_a_changed_status_is_listed_and_left_out_of_the_differences(tmp_path):
    base = grid_errors()
    broken = ("log-barrier", "noise", "nominal", 1)
    comparison = compare_folders(write_run(tmp_path / "a", base), write_run(tmp_path / "b", base, failed={broken}))
    [change] = comparison.status_changes
    assert change.case == "log-barrier/nominal__noise__seed1" and change.kind == "now fails"
    assert (change.status_a, change.status_b) == ("converged", "failed") and "synthetic failure" in change.reason_b
    cell = cells_by(comparison)[("log-barrier", "noise")]
    assert cell.paired == 6 and cell.failures_a == 0 and cell.failures_b == 1
    assert cell.difference("weight_error").pairs == 5 and cell.verdict == SAME
    back = compare_folders(tmp_path / "b", tmp_path / "a")
    assert [s.kind for s in back.status_changes] == ["now solved"]


def test_cases_in_one_run_only_are_named_not_paired(tmp_path):
    base = grid_errors()
    fewer = {case: e for case, e in base.items() if case[3] != 2}  # B lacks seed 2
    comparison = compare_folders(write_run(tmp_path / "a", base), write_run(tmp_path / "b", fewer))
    cell = cells_by(comparison)[("bilevel", "ideal")]
    assert cell.paired == 4 and cell.cases_a == 6 and cell.cases_b == 4 and not cell.only_b
    assert cell.only_a == ("bilevel/nominal__ideal__seed2", "bilevel/penalize-knee__ideal__seed2")


def test_a_single_pair_has_no_interval_and_no_verdict():
    one = {("bilevel", "ideal", "nominal", 0): 0.01}
    comparison = compare_results(_records(one), _records({k: 0.2 for k in one}))
    [cell] = comparison.cells
    d = cell.difference("weight_error")
    assert d.pairs == 1 and d.interval is None and d.difference == pytest.approx(0.19) and cell.verdict == NA


def test_a_new_config_pairs_with_the_old_one_and_says_so(tmp_path):
    base = grid_errors()
    halved = {case: e / 2 if case[0] == "log-barrier" else e for case, e in base.items()}
    a = write_run(tmp_path / "a", base)
    b = write_run(tmp_path / "b", halved, configs={"log-barrier": {"n_random": 5}})
    comparison = compare_folders(a, b)
    [label] = {c.label for c in comparison.cells if c.algorithm == "log-barrier"}
    assert label.startswith("log-barrier [defaults -> cfg ") and comparison.paired == len(base)
    assert {c.verdict for c in comparison.cells if c.algorithm == "log-barrier"} == {BETTER}
    assert {c.verdict for c in comparison.cells if c.algorithm == "bilevel"} == {SAME}
    assert all(c.config_b == {"n_random": 5} and c.config_a == {} for c in comparison.cells if c.label == label)


def test_two_configs_in_one_run_pair_by_config(tmp_path):
    base = {case: e for case, e in grid_errors().items() if case[0] == "log-barrier"}
    a = write_run(tmp_path / "a", base)
    write_run(a, base, configs={"log-barrier": {"n_random": 5}})  # A holds both configs
    b = write_run(tmp_path / "b", base, configs={"log-barrier": {"n_random": 5}})
    comparison = compare_folders(a, b)
    assert comparison.paired == len(base)
    [paired] = {c.label for c in comparison.cells if c.paired}
    assert paired.startswith("log-barrier [cfg ") and "->" not in paired
    unpaired = [c for c in comparison.cells if not c.paired]  # the default config's cases: A only
    assert {c.label for c in unpaired} == {"log-barrier"} and {c.verdict for c in unpaired} == {NA}
    assert sum(len(c.only_a) for c in unpaired) == len(base)


def test_no_case_in_common_and_a_bad_level_are_refused(tmp_path):
    a = write_run(tmp_path / "a", {("bilevel", "ideal", "nominal", 0): 0.01})
    b = write_run(tmp_path / "b", {("log-barrier", "ideal", "nominal", 0): 0.01})
    with pytest.raises(ValueError, match="no case in common"):
        compare_folders(a, b)
    with pytest.raises(ValueError, match="between 0 and 1"):
        compare_folders(a, a, level=1.0)
    with pytest.raises(ValueError, match="no case results"):
        compare_folders(a, (tmp_path / "empty").mkdir() or tmp_path / "empty")


def test_the_level_widens_the_interval():
    base = grid_errors()
    rng = np.random.default_rng(2)
    noisy = {case: max(0.0, e + 0.01 + float(rng.normal(0, 0.01))) for case, e in base.items()}
    narrow = compare_results(_records(base), _records(noisy), level=0.5).cells[0].difference("weight_error")
    wide = compare_results(_records(base), _records(noisy), level=0.99).cells[0].difference("weight_error")
    assert wide.interval[0] < narrow.interval[0] < narrow.interval[1] < wide.interval[1]
    again = compare_results(_records(base), _records(noisy), level=0.5).cells[0].difference("weight_error")
    assert again.interval == narrow.interval  # seeded


@pytest.mark.parametrize(
    ("difference", "interval", "expected"),
    [
        (0.01, (0.005, 0.015), WORSE),
        (-0.01, (-0.015, -0.005), BETTER),
        (0.01, (-0.001, 0.02), SAME),
        (0.0, (0.0, 0.0), SAME),
        (5e-5, (4e-5, 6e-5), SAME),  # within the tolerance
        (0.01, None, NA),
        (math.nan, (0.0, 1.0), NA),
    ],
)
def test_verdict(difference, interval, expected):
    assert verdict(difference, interval, 1e-4) == expected


def _records(errs: dict[tuple, float]):
    return [synthetic_result(alg, ws, cond, seed, weight_error=e) for (alg, cond, ws, seed), e in errs.items()]


def test_transfer_scores_are_compared_where_both_cases_have_one():
    import dataclasses

    base = {case: e for case, e in grid_errors().items() if case[:2] == ("bilevel", "ideal")}

    def moved(records, excess):
        transfer = {"speed": 0.34, "status": "Solve_Succeeded", "trajectory_error": 0.1}
        return [dataclasses.replace(r, transfer=transfer | {"excess_cost": excess + 0.01 * r.seed}) for r in records]

    comparison = compare_results(moved(_records(base), 0.05), moved(_records(base), 0.02))
    [cell] = comparison.cells
    assert cell.difference("transfer_excess").verdict == BETTER
    assert cell.difference("transfer_excess").difference == pytest.approx(-0.03)
    assert cell.difference("transfer_error").verdict == SAME and cell.verdict == SAME


def test_a_case_given_twice_is_refused():
    records = _records({("bilevel", "ideal", "nominal", 0): 0.01})
    with pytest.raises(ValueError, match="holds the case bilevel/nominal__ideal__seed0 twice"):
        compare_results(records * 2, records)


def test_the_intervals_do_not_depend_on_the_order_the_cases_come_in():
    base = grid_errors()
    rng = np.random.default_rng(4)
    noisy = {case: max(0.0, e + float(rng.normal(0.005, 0.01))) for case, e in base.items()}
    a, b = _records(base), _records(noisy)
    first = compare_results(a, b)
    order = rng.permutation(len(a))
    again = compare_results([a[i] for i in order], [b[i] for i in reversed(order)])
    assert [c.differences for c in again.cells] == [c.differences for c in first.cells]


def test_a_case_of_another_cost_basis_is_another_case():
    """``nominal`` of the effort basis and of the energetics basis are two truths: never paired."""
    effort = [synthetic_result("bilevel", "nominal", "ideal", s, weight_error=0.01) for s in (0, 1)]
    energetics = [
        synthetic_result("bilevel", "nominal", "ideal", s, weight_error=0.2, basis="energetics") for s in (0, 1)
    ]
    comparison = compare_results(effort, [*effort, *energetics])
    assert comparison.paired == 2
    assert {c.label: c.verdict for c in comparison.cells} == {"bilevel": SAME, "bilevel (energetics)": NA}
    with pytest.raises(ValueError, match="no case in common"):  # one label each side: still not paired
        compare_results(effort, energetics)
