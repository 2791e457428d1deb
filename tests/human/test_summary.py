"""The opening of the human board: one ranked table over the same predictions, a headline
computed from it, and the case figures; records made up by hand (nothing is solved)."""

from __future__ import annotations

import dataclasses
import math

import pytest

from ioc_bench.human.board import markdown
from ioc_bench.human.case import HumanCaseSpec
from ioc_bench.human.opening import figure_caption, rankings
from ioc_bench.human.record import HumanResult, SpeedScore, check_values
from ioc_bench.human.scoring import NOMINAL, beats, skill_score
from ioc_bench.runner.leaderboard import write_leaderboard

#: The person's change of leg angles between the training speed and each predicted one (deg);
#: copying the training step is off by exactly this much.
CHANGE = 3.0


def _score(code: str, role: str, source: str, rmse: float, adaptation: float, step: float) -> SpeedScore:
    """A score consistent with its own numbers (:func:`check_values`); a prediction carries the
    baselines: population's change 2 deg off the person's (R^2 1 - 4/9), power law 0.05."""
    nominal, floor = 10.0, min(rmse, 10.0)
    predicted = role == "prediction"
    copy = CHANGE if predicted else math.nan
    return SpeedScore(
        code, role, 0.3, 0.6, "Solve_Succeeded", 1.0, rmse, nominal, floor,
        "estimate" if rmse <= nominal else NOMINAL, skill_score(rmse, nominal, floor), beats(rmse, nominal),
        source, copy, beats(rmse, copy) if predicted else None, adaptation if predicted else math.nan, copy,
        5.0 if predicted else math.nan, 0.1, 0.2, 1.0,
        step_length_error=step if predicted else math.nan,
        continued_from=source,
        change_r2=1 - (adaptation / CHANGE) ** 2 if predicted else math.nan,
        copy_step_length_error=0.1 if predicted else math.nan,
        power_law_step_length_error=0.05 if predicted else math.nan,
        population_rmse_deg=2.5 if predicted else math.nan,
        population_adaptation_deg=2.0 if predicted else math.nan,
    )  # fmt: skip


def _record(algorithm: str, *, rmse: float, adaptation: float, step: float = 0.3, train: str = "T05",
            predict: tuple[str, ...] = ("T04", "T06"), subject: str = "WBDS01", **case) -> HumanResult:  # fmt: skip
    """A made-up one-speed record whose every prediction has ``rmse`` and ``adaptation``."""
    spec = HumanCaseSpec(subject, train, predict, algorithm, **case)
    scores = {
        code: _score(code, spec.role(code), spec.train if spec.role(code) == "prediction" else "", rmse, adaptation,
                     step)
        for code in spec.scored
    }  # fmt: skip
    identity = {f: getattr(spec, f) for f in HumanCaseSpec.identity_fields()}
    record = HumanResult(
        **identity, family="bilevel", features=spec.features, status="converged", reason="",
        weights=(0.6, 0.8, 0.0), wall_time=1.0, n_solves=2, scoring_time=2.0, scores=scores,
    )  # fmt: skip
    check_values(record)
    return record


def _ranked(page: str) -> list[str]:
    """The model column of the ranked table, top down."""
    lines = page.splitlines()
    start = next(i for i, line in enumerate(lines) if line.startswith("| # | model |"))
    rows = []
    for line in lines[start + 2 :]:
        if not line.startswith("|"):
            break
        rows.append(line.split(" | ")[1])
    return rows


def _headline(page: str) -> str:
    return next(line for line in page.splitlines() if line.startswith("On the change of gait with speed"))


def test_the_ranked_table_follows_the_numbers_and_the_headline_follows_the_table() -> None:
    """Cost "a" changes 1 deg off the person's (R^2 1 - 1/9 = 0.89, above the population's
    0.56) with angles 2 deg off (below copy's 3); "b" changes 4 deg off (R^2 -0.78) with
    angles 9 deg off. Then "a" gets worse than the population's change and copy: the order
    and the headline turn with it."""
    good, bad = _record("a", rmse=2.0, adaptation=1.0), _record("b", rmse=9.0, adaptation=4.0)
    page = markdown([good, bad])
    assert _ranked(page) == [
        "a", "population's change (baseline)", "copy (baseline)", "b", "power law, step length only (baseline)",
    ]  # fmt: skip
    assert "| 1 | a | 0.89 | 0.300 | 2.00 | 2/2 | 0 |" in page
    headline = _headline(page)
    assert headline.startswith("On the change of gait with speed, a ranks first (change R^2 0.89)")
    assert "1 of the 2 cost models beat the population's change" in headline
    assert "1 of the 2 cost models beat copying the person's training step" in headline
    assert "per prediction 2 of 4 beat copy" in headline

    worse = _record("a", rmse=4.0, adaptation=2.5)  # R^2 1 - 6.25/9 = 0.31, angles 4 deg off
    page = markdown([worse, bad])
    assert _ranked(page) == [
        "population's change (baseline)", "a", "copy (baseline)", "b", "power law, step length only (baseline)",
    ]  # fmt: skip
    headline = _headline(page)
    assert headline.startswith("On the change of gait with speed, the population's change ranks first (change R^2")
    assert "the best cost model, a, scores 0.31" in headline
    assert "none of the 2 cost models beats the population's change" in headline
    assert "none of the 2 cost models beats copying the person's training step" in headline
    assert "none of the 2 cost models beats the power law" in headline  # 0.3 against 0.05


def test_the_ranking_covers_the_design_every_algorithm_ran_and_ranks_partial_rows_last() -> None:
    """ "a" ran one speed at two training speeds and two speeds; "c" one speed at one training
    speed only: the ranking is over one speed's four predictions, and "c", the best on the
    change over its two, ranks after every row over all four."""
    a = [_record("a", rmse=5.0, adaptation=2.8, train=t, predict=p) for t, p in (("T05", ("T04", "T06")),
                                                                             ("T04", ("T03", "T05")))]  # fmt: skip
    two = _record("a", rmse=1.0, adaptation=0.1, train="T04", predict=("T03", "T06"), also_train=("T05",))
    c = _record("c", rmse=5.0, adaptation=0.5)
    (ranking,) = rankings([*a, two, c])
    assert ranking.design == "one speed" and ranking.every and ranking.total == 4
    labels = [r["label"] for r in ranking.rows]
    assert labels[-1] == "c" and labels.index("power law, step length only (baseline)") == len(labels) - 2
    page = markdown([*a, two, c])
    assert "| 5 | c | 0.97 | 0.300 | 5.00 | 2/4 | 0 |" in page
    assert "the design every algorithm ran" in page and "4 predictions of 1 subject (WBDS01)" in page
    # the detailed tables are still there, below the summary
    assert page.index("**Ranked summary**") < page.index("### Details") < page.index("| a | speed-and-step | two")


def test_the_figures_are_image_links_with_captions_and_the_old_call_still_works(tmp_path) -> None:
    records = [_record("a", rmse=2.0, adaptation=1.0)]
    plain = markdown(records)
    assert "![" not in plain and plain.startswith("## Human track\n\n**Ranked summary**")
    assert "No intervals: the predictions come from 1 subject" in plain
    figures = ["figures/bilevel_WBDS02__train-T05__from-WBDS01+WBDS03__predict-T03-T04-T05-T06.png",
               "figures/log-barrier_WBDS03__train-T04+T05+T06__predict-T03__seed0__task-speed.png"]  # fmt: skip
    page = markdown(records, figures)
    assert (
        "![bilevel, WBDS02: trained at T05 (population WBDS01, WBDS03), predicting T03, T04, T05, T06]"
        f"({figures[0]})" in page
    )
    assert f"![log-barrier, WBDS03: trained at T04, T05 and T06, predicting T03 (task speed)]({figures[1]})" in page
    assert page.index("![") < page.index("### Details")
    assert figure_caption("robustness.png") is None

    board = tmp_path / "board"
    (board / "figures").mkdir(parents=True)
    for name in ("a_WBDS01__train-T05__predict-T04-T06.png", "robustness.png", "notes.txt"):
        (board / "figures" / name).write_bytes(b"\x89PNG")
    write_leaderboard(records, board, "results-human")
    readme = (board / "README.md").read_text()
    assert (
        "![a, WBDS01: trained at T05, predicting T04, T06](figures/a_WBDS01__train-T05__predict-T04-T06.png)" in readme
    )
    assert "robustness.png" not in readme


def test_a_failed_case_counts_its_predictions_as_failures() -> None:
    ok = _record("a", rmse=2.0, adaptation=1.0)
    failed = dataclasses.replace(
        _record("b", rmse=2.0, adaptation=1.0), status="failed", reason="x", scores={}, weights=(math.nan,) * 3
    )
    rows = {r["label"]: r for r in rankings([ok, failed])[0].rows}
    assert rows["b"]["predictions"] == 2 and rows["b"]["failures"] == 2 and math.isnan(rows["b"]["change_r2"])
    assert rows["a"]["failures"] == 0 and rows["a"]["change_r2"] == pytest.approx(1 - 1 / 9)


def test_every_scored_speed_is_a_csv_row_and_a_failed_case_one_row_with_its_reason() -> None:
    import csv
    import io

    from ioc_bench.human.board import CSV_COLUMNS, cases_csv

    ok = _record("a", rmse=2.0, adaptation=1.0)
    failed = dataclasses.replace(
        _record("b", rmse=2.0, adaptation=1.0), status="failed", reason="x\ny", scores={}, weights=(math.nan,) * 3
    )
    rows = list(csv.DictReader(io.StringIO(cases_csv([ok, failed]))))
    assert tuple(rows[0]) == CSV_COLUMNS
    assert [r["speed"] for r in rows if r["algorithm"] == "a"] == list(ok.scores)
    (b,) = [r for r in rows if r["algorithm"] == "b"]
    assert b["speed"] == "" and b["reason"] == "x y" and b["weights"] == ""
