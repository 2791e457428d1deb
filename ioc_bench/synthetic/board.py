"""The synthetic track's part of the leaderboard: (algorithm, config) x condition summaries.

A row is an algorithm with one config (its defaults, or ``[cfg <digest>]`` with the fields
that differ listed in the header), so results of different configs never share a cell.
With 3 or more seeds per weight set a 95 % bootstrap confidence interval of the mean weight
error is given, resampling seeds within each weight set
(:mod:`ioc_bench.synthetic.statistics`); robustness-suite results add a table of robustness
AUCs (:mod:`ioc_bench.synthetic.robustness`). :data:`SECTION` is what the board
(:mod:`ioc_bench.runner.leaderboard`) is handed: the Markdown, ``cells.csv``, ``cases.csv``
and the ``cells`` and ``cases`` of ``leaderboard.json``.
"""

from __future__ import annotations

import csv
import io
import json
from collections import defaultdict
from collections.abc import Sequence
from dataclasses import asdict, dataclass, fields
from pathlib import Path
from typing import Any

import numpy as np

from ioc_bench.bases import DEFAULT_BASIS, get_basis
from ioc_bench.model.catalogue import DEFAULT_MODEL, MODELS, get_model
from ioc_bench.runner.protocol import BoardSection
from ioc_bench.synthetic.case import CaseResult
from ioc_bench.synthetic.conditions import CONDITIONS
from ioc_bench.synthetic.ranking import grid_lines, paper_lines, rank, ranking_lines
from ioc_bench.synthetic.results import kept_record, result_config, run_label
from ioc_bench.synthetic.robustness import auc_table
from ioc_bench.synthetic.statistics import MIN_SEEDS_FOR_CI, RESAMPLES, stratified_mean_ci
from ioc_bench.synthetic.statistics import finite_mean as _mean
from ioc_bench.weights import WEIGHT_SETS, penalised_feature

#: The columns of ``cases.csv``.
CSV_COLUMNS = (
    "model", "algorithm", "basis", "weight_set", "condition", "seed", "status", "features", "weights",
    "true_weights", "weight_error", "trajectory_error", "region_holds_truth", "model_rejected", "time_s",
    "forward_solves", "reason",
)  # fmt: skip


@dataclass(frozen=True)
class Cell:
    """Summary of one algorithm with one config under one condition.

    ``label`` is the row's name (``algorithm`` or ``algorithm [cfg <digest>]``) and
    ``config`` the fields of its config that differ from the algorithm's defaults.
    """

    algorithm: str
    family: str
    label: str
    config: dict
    condition: str
    cases: int
    model: str
    failures: int
    seeds: tuple[int, ...]
    weight_error: float
    weight_error_ci: tuple[float, float] | None
    trajectory_error: float
    found_trajectory_error: float
    wall_time: float
    forward_solves: float
    largest_recovered: int
    largest_checked: int
    regions: int
    covered: int
    region_width: float
    transfers: int
    transfer_error: float
    transfer_excess: float
    tested: int = 0
    flagged: int = 0
    fitting_regions: int = 0
    fitting_covered: int = 0
    basis: str = DEFAULT_BASIS


def penalised_is_largest(result: CaseResult) -> bool | None:
    """For a penalize-* case: is the penalised feature's estimated weight the largest?"""
    feature = penalised_feature(result.weight_set, result.features)
    if feature is None or result.failed:
        return None
    return int(np.argmax(result.weights)) == result.features.index(feature)


def row_condition(result: CaseResult) -> str:
    """The row a result belongs to: its condition, apart for weight sets other than the
    model's named ones (the ``unseen`` suite), so a row never mixes the two designs."""
    named = get_basis(result.basis).weight_sets(get_model(result.model)) if result.model in MODELS else WEIGHT_SETS
    return result.condition if result.weight_set in named else f"{result.condition}, other weight sets"


def summarise(results: Sequence[CaseResult]) -> list[Cell]:
    """One :class:`Cell` per (model, algorithm, config, condition), conditions in catalogue order."""
    groups: dict[tuple[str, str, str], list[CaseResult]] = defaultdict(list)
    for r in results:
        groups[(r.model, run_label(r), row_condition(r))].append(r)
    order = {c: i for i, c in enumerate(CONDITIONS)}
    models = {m: i for i, m in enumerate(MODELS)}
    cells = []
    for (model, label, cond), rs in sorted(
        groups.items(), key=lambda kv: (models.get(kv[0][0], 99), kv[0][0], kv[0][1], order.get(kv[0][2], 99), kv[0][2])
    ):
        ok = [r for r in rs if not r.failed]
        strata = _by_weight_set(ok)  # successful cases only: failures are not replicates
        enough = bool(strata) and min(len({r.seed for r in g}) for g in strata) >= MIN_SEEDS_FOR_CI
        checks = [c for c in (penalised_is_largest(r) for r in rs) if c is not None]
        regions = [r for r in ok if r.uncertainty is not None]
        tested = [r for r in ok if r.misfit is not None]
        fitting = [r for r in regions if r.misfit is False]
        moved = [r.transfer for r in ok if r.transfer and _scored_transfer(r.transfer)]
        cells.append(
            Cell(
                algorithm=rs[0].algorithm,
                family=rs[0].family,
                label=label,
                config=result_config(rs[0]),
                condition=cond,
                cases=len(rs),
                model=model,
                failures=len(rs) - len(ok),
                seeds=tuple(sorted({r.seed for r in rs})),
                weight_error=_mean([r.weight_error for r in ok]),
                weight_error_ci=stratified_mean_ci([[r.weight_error for r in g] for g in strata]) if enough else None,
                trajectory_error=_mean([r.trajectory_error for r in ok]),
                found_trajectory_error=_mean(
                    [r.found_trajectory_error for r in ok if r.found_trajectory_error is not None]
                ),
                wall_time=_mean([r.wall_time for r in rs]),
                forward_solves=_mean([r.n_solves for r in rs]),
                largest_recovered=sum(checks),
                largest_checked=len(checks),
                regions=len(regions),
                covered=sum(bool(r.covered) for r in regions),
                region_width=_mean([_width(r.uncertainty) for r in regions]),
                transfers=len(moved),
                transfer_error=_mean([t["trajectory_error"] for t in moved]),
                transfer_excess=_mean([t["excess_cost"] for t in moved]),
                tested=len(tested),
                flagged=sum(bool(r.misfit) for r in tested),
                fitting_regions=len(fitting),
                fitting_covered=sum(bool(r.covered) for r in fitting),
                basis=rs[0].basis,
            )
        )
    return cells


def _scored_transfer(transfer: dict) -> bool:
    """Whether a transfer was solved and scored (its two scores are numbers)."""
    values = [transfer.get(k) for k in ("trajectory_error", "excess_cost")]
    return all(isinstance(v, (int, float)) and np.isfinite(v) for v in values)


def _width(region: dict) -> float:
    return float(np.mean(np.subtract(region["upper"], region["lower"])))


def _fmt(x: float, digits: int = 4) -> str:
    return "n/a" if not np.isfinite(x) else f"{x:.{digits}f}"


def is_synthetic_figure(path: str) -> bool:
    """Whether a figure beside the board is the synthetic track's: the names ``ioc-bench
    figures`` writes (:func:`ioc_bench.viz.figures.output_names`: ``figure4_*``, ``figure5_*``,
    ``figure6``, ``robustness``)."""
    name = Path(path).stem
    return name == "robustness" or name == "figure6" or name.startswith(("figure4_", "figure5_"))


def cases_csv(results: Sequence[CaseResult]) -> str:
    """Every synthetic case as one CSV row (the board's per-case table)."""
    buffer = io.StringIO()
    writer = csv.writer(buffer, lineterminator="\n")
    writer.writerow(CSV_COLUMNS)
    order = {c: i for i, c in enumerate(CONDITIONS)}
    for r in sorted(results, key=lambda r: (r.model, run_label(r), order.get(r.condition, 99), r.weight_set, r.seed)):
        writer.writerow(
            [
                r.model, run_label(r), r.basis, r.weight_set, r.condition, r.seed, r.status,
                " ".join(r.features), " ".join(f"{w:.6g}" for w in r.weights),
                " ".join(f"{w:.6g}" for w in r.true_weights), _csv_number(r.weight_error),
                _csv_number(r.trajectory_error), "" if r.covered is None else r.covered,
                "" if r.misfit is None else r.misfit, f"{r.wall_time:.3f}", r.n_solves,
                " ".join(r.reason.split()) if r.failed else "",
            ]
        )  # fmt: skip
    return buffer.getvalue()


def _csv_number(x: float) -> str:
    return "" if not np.isfinite(x) else f"{x:.6g}"


def sections(results: Sequence[CaseResult], figures: Sequence[str] = ()) -> list[str]:
    """The synthetic track: its first screen (ranking, headline figure, grid, the paper's
    findings), then the details (method, every cell's scores, calibration, robustness);
    ``figures`` are the track's figure files present beside the board (relative paths)."""
    cells = summarise(results)
    lines = [
        "## Synthetic track",
        "",
        *_first_screen(results, cells, figures),
        "",
        "### Details",
        "",
        *_details(results, cells),
        "",
        *_calibration(cells),
        "",
        *_robustness(results),
    ]
    return lines


def _first_screen(results: Sequence[CaseResult], cells: Sequence[Cell], figures: Sequence[str]) -> list[str]:
    ranked = rank(results, row_condition)
    headline = [f for f in figures if Path(f).name == "robustness.png"]
    others = [f for f in figures if f not in headline]
    lines = [
        "### Ranking",
        "",
        "Mean weight error (|estimated - true| of the unit-norm weights, lower is better) over the paper's six "
        "conditions, each condition counted once; the 95 % interval resamples seeds within each condition and "
        "weight set (it covers repeating this study with these weight sets, not other weights). *Hardest*: the "
        "condition with the largest mean error. *Regions hold truth*: the algorithm's own 95 % weight regions "
        "that contain the true weights (`-`: it reports none). Rows that ran only some of the paper's conditions "
        "are listed after the ranked ones. Time: the algorithm's own, per case.",
        "",
        *ranking_lines(ranked, _fmt),
    ]
    shown = [f"![Weight error against perturbation severity]({f})" for f in headline]
    if others:  # below the headline figure, in its paragraph
        shown.append("Figures: " + ", ".join(f"[{Path(f).stem}]({f})" for f in others) + ".")
    lines += ["", *shown] if shown else []
    lines += [
        "",
        "### Weight error by condition",
        "",
        "Mean weight error of each algorithm (rows) under each condition (columns); `-`: not run.",
        "",
        *grid_lines(cells, _fmt),
        "",
        "### Against the paper's findings",
        "",
        "The paper's finding per condition (Rebula et al. 2019, section III) beside each algorithm's mean weight "
        "error on the paper's model (walker) and cost (the effort basis); in bold each algorithm's hardest "
        "condition; *largest k/n*: cases whose penalised weight came out the largest.",
        "",
        *paper_lines([c for c in cells if c.basis == DEFAULT_BASIS], _fmt),
    ]
    return lines


def _details(results: Sequence[CaseResult], cells: Sequence[Cell]) -> list[str]:
    seeds = sorted({r.seed for r in results})
    lines = [
        "**Method.** Each case runs one IOC algorithm on one demonstrated step: the best of 15 starts of the "
        "trajectory optimizer for the true weights (multi-start seed = the case's seed), verified as a local "
        "minimum, observed as the condition allows (noise, torques unmeasured, wrong model, wrong task, "
        "distractor features; docs/spec.md, *Conditions*; the observation holds positions, velocities and torques "
        "only). "
        "Weight error: mean |estimated - true| of the unit-norm weights over the features the IOC weighed. "
        "Trajectory error (the paper's): sum over knots and segments of squared segment-angle and "
        "angular-velocity differences to the observed step, of the estimated weights' optimal step re-solved in "
        "the observation's basin (*re-solved*) and of the step the algorithm itself found for its output "
        "(*found*, the paper's reading; n/a for methods without one). "
        "Time and forward solves are the algorithm's own (scoring excluded). Failed cases count in *failures* "
        "and are left out of the means.",
        "",
        f"**Seeds:** {', '.join(map(str, seeds))}. A seed is a new experiment: it re-solves the demonstration "
        "from its own multi-start, draws its own observation noise and seeds the algorithm. "
        + (
            f"The 95 % interval is a percentile bootstrap ({RESAMPLES} resamples) of the cell's mean weight error "
            "that resamples the seeds within each weight set (the weight sets are a fixed design, not a sample): it "
            "covers what repeating the study with these weight sets would give, not other weight sets. "
            + _demo_spread_sentence(results)
            + f"Given where every weight set has {MIN_SEEDS_FOR_CI}+ successful seeds."
            if any(c.weight_error_ci for c in cells)
            else f"No confidence intervals: they need {MIN_SEEDS_FOR_CI}+ seeds per weight set; "
            "this is a single run, so small differences are not significant."
        ),
        "",
        _configs_line(cells, results),
        "",
        "**Every cell** (model, algorithm, condition) is a row of [`cells.csv`](cells.csv) beside this page: its "
        "cases, failures, mean weight error and interval; the trajectory errors (re-solved, found); *covered* of "
        "*regions*: successful cases whose 95 % weight region (the algorithm's own) holds the true weights, and "
        "the regions' mean width (mean of upper - lower); *transfer*: the estimated weights' optimum at the other "
        "speed (0.34 for a 0.27 demonstration, 0.27 for 0.34) under the true model against the true weights' "
        "optimum there, as the paper's trajectory error and the excess cost under the true weights (relative; none "
        "for the multi-trial conditions, which observe both); the algorithm's time and forward solves; the "
        "penalised weight came out largest (*largest_recovered* of *largest_checked*); the misfit test's "
        "*flagged* of *tested*. **Every case** (estimated weights, errors, status, time) is a row of "
        "[`cases.csv`](cases.csv) and a record in `leaderboard.json`.",
    ]
    return lines


def _calibration(cells: Sequence[Cell]) -> list[str]:
    """How well each algorithm's 95 % regions cover the truth, over every successful case and
    over the cases whose model the misfit test does not reject; and how often it rejects."""
    by: dict[tuple[str, str], list[Cell]] = defaultdict(list)
    for c in cells:
        by[(c.model, c.label)].append(c)
    share = lambda cov, n: f"{cov / n:.2f} ({cov}/{n})" if n else "-"  # noqa: E731
    lines = [
        "### Calibration of the 95 % weight regions",
        "",
        "Share of successful cases whose region holds the true weights (a calibrated 95 % region: about 0.95), "
        "with the number of cases behind it, and the mean width; noise conditions apart; and over the cases "
        "whose model fits the observation (the algorithm's misfit test: its residual against the noise "
        "estimated from the observation; a region of a rejected model is conditional on it).",
        "",
        "| model | algorithm | all conditions | noise conditions | model not rejected | mean width |",
        "|---|---|---|---|---|---|",
    ]
    for (model, label), cs in by.items():
        regions = sum(c.regions for c in cs)
        if not regions:
            lines.append(f"| {model} | {label} | reports no region | - | - | - |")
            continue
        noisy = [c for c in cs if "noise" in c.condition]
        n_noisy = sum(c.regions for c in noisy)
        fitting = share(sum(c.fitting_covered for c in cs), sum(c.fitting_regions for c in cs))
        width = _mean([c.region_width for c in cs if c.regions])
        lines.append(
            f"| {model} | {label} | {share(sum(c.covered for c in cs), regions)} | "
            f"{share(sum(c.covered for c in noisy), n_noisy)} | {fitting} | {_fmt(width, 3)} |"
        )
    return [*lines, "", _misfit_sentence(cells)]


def _misfit_sentence(cells: Sequence[Cell]) -> str:
    """How often each algorithm's misfit test rejects its model, over every condition (per
    condition: ``flagged`` and ``tested`` in ``cells.csv``)."""
    by: dict[str, list[Cell]] = defaultdict(list)
    for c in cells:
        if c.tested:
            by[f"{c.label} ({c.model})" if c.model != DEFAULT_MODEL else c.label].append(c)
    if not by:
        return "No algorithm here tests whether its model fits the observation."
    shares = [f"{label} {sum(c.flagged for c in cs)}/{sum(c.tested for c in cs)}" for label, cs in by.items()]
    return (
        "Cases whose model the misfit test rejects, over every condition (flagged / tested; per condition in "
        "`cells.csv`): " + "; ".join(shares) + "."
    )


def cells_csv(cells: Sequence[Cell]) -> str:
    """Every cell as one CSV row (its interval as two columns)."""
    buffer = io.StringIO()
    writer = csv.writer(buffer, lineterminator="\n")
    names = [f.name for f in fields(Cell) if f.name not in ("config", "weight_error_ci", "seeds")]
    writer.writerow([*names, "weight_error_ci_low", "weight_error_ci_high", "seeds", "config"])
    for c in cells:
        low, high = c.weight_error_ci or ("", "")
        values = [getattr(c, n) for n in names]
        writer.writerow(
            [*(_csv_number(v) if isinstance(v, float) else v for v in values), _csv_value(low), _csv_value(high),
             " ".join(map(str, c.seeds)), json.dumps(c.config, sort_keys=True)]
        )  # fmt: skip
    return buffer.getvalue()


def _csv_value(x: float | str) -> str:
    return x if isinstance(x, str) else _csv_number(x)


def _robustness(results: Sequence[CaseResult]) -> list[str]:
    """The robustness AUC table (rows with a complete axis of the robustness suite)."""
    table = auc_table(results)
    if not table:
        return []
    lines = [
        "### Robustness (beyond the paper)",
        "",
        "Mean weight error over each perturbation's severity range (area under the error-vs-severity curve "
        "divided by the range; noise 0-10 % of span, leg-mass and speed errors -20..+20 %; `robustness` suite). "
        "Lower is more robust; the curves with their intervals are in `figures/robustness.png`.",
        "",
        "| algorithm | noise | mass | speed | robustness AUC (mean) |",
        "|---|---|---|---|---|",
    ]
    for label, row in sorted(table.items(), key=lambda kv: kv[1]["mean"]):
        axes = " | ".join(_fmt(row.get(a, float("nan"))) for a in ("noise", "mass", "speed"))
        lines.append(f"| {label} | {axes} | {_fmt(row['mean'])} |")
    return lines


def demo_spread(results: Sequence[CaseResult]) -> float | None:
    """Largest relative difference of a demonstration feature between seeds of the same
    weight set, model and speed (None if no demonstration was solved for two seeds)."""
    by: dict[tuple[str, str, float], list[dict[str, float]]] = defaultdict(list)
    for r in results:
        if r.demo_features:  # one model's weight set names another model's set of features
            by[(r.model, r.weight_set, r.demo_speed)].append(r.demo_features)
    spreads = [
        (max(vals) - min(vals)) / max(abs(v) for v in vals)
        for demos in by.values()
        if len(demos) > 1
        for vals in ([d[f] for d in demos] for f in demos[0])
        if max(abs(v) for v in vals) > 0
    ]
    return max(spreads) if spreads else None


def _demo_spread_sentence(results: Sequence[CaseResult]) -> str:
    spread = demo_spread(results)
    if spread is None or spread > 1e-3:
        return ""
    return (
        f"The demonstrations of different seeds differ by at most {spread:.1g} (relative) in any feature: "
        "without noise a deterministic algorithm gives one value per weight set, and its interval is a point. "
    )


def _by_weight_set(results: Sequence[CaseResult]) -> list[list[CaseResult]]:
    groups: dict[str, list[CaseResult]] = defaultdict(list)
    for r in results:
        groups[r.weight_set].append(r)
    return list(groups.values())


def _configs_line(cells: Sequence[Cell], results: Sequence[CaseResult]) -> str:
    """The header line saying which config each row used, in full (e.g. where
    ``log-barrier``'s forward solves start)."""
    configs = {c.label: c.config for c in cells}
    effective = {run_label(r): r.config for r in results}
    parts = [
        f"`{label}`: "
        + (f"defaults except `{json.dumps(cfg, sort_keys=True)}`" if cfg else "the algorithm's defaults")
        + f" (in full: `{json.dumps(effective.get(label, {}), sort_keys=True)}`)"
        for label, cfg in configs.items()
    ]
    return "**Configs** (a row never mixes configs): " + "; ".join(parts) + "."


def files(results: Sequence[CaseResult]) -> tuple[dict[str, Any], dict[str, str]]:
    """The track's entries of ``leaderboard.json`` (every cell, every case without its history,
    with its row's label) and its tables (``cells.csv``, ``cases.csv``); empty ones for no results."""
    cells = summarise(results)
    data = {
        "cells": [asdict(c) for c in cells],
        "cases": [
            {k: v for k, v in r.to_dict().items() if k not in ("history", "oracle")} | {"label": run_label(r)}
            for r in results
        ],
    }
    return data, {"cells.csv": cells_csv(cells), "cases.csv": cases_csv(results)}


def summary(results: Sequence[CaseResult]) -> dict[str, Any]:
    """What ``--json`` reports of the track: every cell."""
    return {"cells": [c.__dict__ for c in summarise(results)]}


#: The synthetic track's part of the board.
SECTION = BoardSection(
    markdown=sections,
    files=files,
    tables=("cells.csv", "cases.csv"),
    cases_key="cases",
    parse_kept=kept_record,
    summary=summary,
    owns_figure=is_synthetic_figure,
)
