"""The synthetic board's first screen: algorithms ranked, then the algorithm x condition grid
and the paper's findings beside each algorithm's.

The ranking's headline is the weight error over the paper's conditions, each condition
counted once (a condition's cases are its weight sets times seeds; conditions with more
cases would otherwise weigh more). Its interval resamples the seeds within each (condition,
weight set), like a cell's (:mod:`ioc_bench.synthetic.statistics`): it covers repeating the study
with these weight sets, not other weight sets or other conditions. A row that ran only some
of the paper's conditions ranks after the rows that ran all of them.
"""

from __future__ import annotations

import math
from collections import defaultdict
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass

from ioc_bench.model.catalogue import DEFAULT_MODEL
from ioc_bench.synthetic.case import CaseResult
from ioc_bench.synthetic.results import run_label
from ioc_bench.synthetic.statistics import MIN_SEEDS_FOR_CI, stratified_mean_ci
from ioc_bench.synthetic.statistics import finite_mean as _mean

#: The paper's findings, one per condition (Rebula et al. 2019, section III).
PAPER_FINDINGS = {
    "ideal": "weight error < 1 %",
    "ideal-fast": "weight error < 1 %",
    "noise": "penalised weight recovered as the largest; lowest weight error of the perturbed conditions",
    "mass": "penalised weight recovered as the largest",
    "speed": "penalised weight recovered as the largest",
    "distractor": "the hardest: largest weight error (weight attributed to distractors)",
}
#: The conditions the ranking averages: the paper's.
RANKED_CONDITIONS = tuple(PAPER_FINDINGS)


@dataclass(frozen=True)
class Ranked:
    """One row of the ranking: an algorithm with one config (and basis) on one model."""

    model: str
    label: str
    family: str
    conditions: tuple[str, ...]
    weight_error: float
    interval: tuple[float, float] | None
    ideal: float
    hardest: str
    hardest_error: float
    cases: int
    failures: int
    covered: int
    regions: int
    time: float

    @property
    def complete(self) -> bool:
        return len(self.conditions) == len(RANKED_CONDITIONS)


def rank(results: Sequence[CaseResult], row_of: Callable[[CaseResult], str]) -> list[Ranked]:
    """The ranking over the paper's conditions, best first (rows with every paper condition
    first). ``row_of`` gives a result's condition row on the board (the named weight sets'
    rows only are ranked)."""
    groups: dict[tuple[str, str], list[CaseResult]] = defaultdict(list)
    for r in results:
        if row_of(r) in RANKED_CONDITIONS:
            groups[(r.model, run_label(r))].append(r)
    rows = [_ranked(model, label, rs) for (model, label), rs in groups.items()]
    return sorted(rows, key=lambda r: (not r.complete, _order(r.weight_error), r.model, r.label))


def _ranked(model: str, label: str, results: Sequence[CaseResult]) -> Ranked:
    by_condition: dict[str, list[CaseResult]] = defaultdict(list)
    for r in results:
        by_condition[r.condition].append(r)
    conditions = tuple(c for c in RANKED_CONDITIONS if c in by_condition)
    means = {c: _mean([r.weight_error for r in by_condition[c] if not r.failed]) for c in conditions}
    scored = [c for c in conditions if math.isfinite(means[c])]
    hardest = max(scored, key=means.__getitem__, default="")
    ok = [r for r in results if not r.failed]
    regions = [r for r in ok if r.uncertainty is not None]
    return Ranked(
        model=model,
        label=label,
        family=results[0].family,
        conditions=conditions,
        weight_error=_mean([means[c] for c in scored]),
        interval=_interval(by_condition, scored),
        ideal=means.get("ideal", math.nan),
        hardest=hardest,
        hardest_error=means.get(hardest, math.nan),
        cases=len(results),
        failures=len(results) - len(ok),
        covered=sum(bool(r.covered) for r in regions),
        regions=len(regions),
        time=_mean([r.wall_time for r in results]),
    )


def _interval(by_condition: Mapping[str, Sequence[CaseResult]], scored: Sequence[str]) -> tuple[float, float] | None:
    """The interval of the conditions' equal-weight mean: strata are (condition, weight set),
    each condition's share split over its weight sets by their successful cases."""
    strata, shares = [], []
    for c in scored:
        sets: dict[str, list[float]] = defaultdict(list)
        seeds: dict[str, set[int]] = defaultdict(set)
        for r in by_condition[c]:
            if not r.failed:
                sets[r.weight_set].append(r.weight_error)
                seeds[r.weight_set].add(r.seed)
        if min(len(s) for s in seeds.values()) < MIN_SEEDS_FOR_CI:
            return None
        n = sum(len(v) for v in sets.values())
        for values in sets.values():
            strata.append(values)
            shares.append(len(values) / n / len(scored))
    return stratified_mean_ci(strata, shares=shares) if strata else None


def ranking_lines(rows: Sequence[Ranked], fmt) -> list[str]:
    """The ranking as a Markdown table (``fmt`` formats a weight error)."""
    lines = [
        "| rank | algorithm | model | family | weight error, paper's conditions [95 % CI] | ideal | hardest "
        "condition | regions hold truth | failures | time per case (s) |",
        "|---|---|---|---|---|---|---|---|---|---|",
    ]
    for i, r in enumerate(rows, 1):
        ci = "" if r.interval is None else f" [{fmt(r.interval[0])}, {fmt(r.interval[1])}]"
        ran = "" if r.complete else f" ({len(r.conditions)} of {len(RANKED_CONDITIONS)} conditions)"
        hardest = f"{r.hardest} {fmt(r.hardest_error)}" if r.hardest else "-"
        regions = f"{r.covered}/{r.regions}" if r.regions else "-"
        place = str(i) if r.complete else "-"
        lines.append(
            f"| {place} | {r.label} | {r.model} | {r.family or '-'} | {fmt(r.weight_error)}{ci}{ran} "
            f"| {fmt(r.ideal)} | {hardest} | {regions} | {r.failures}/{r.cases} | {r.time:.1f} |"
        )
    return lines


def grid_lines(cells: Sequence, fmt) -> list[str]:
    """Mean weight error per (model, algorithm) row and condition column (``-``: not run);
    ``cells`` are the leaderboard's :class:`~ioc_bench.synthetic.board.Cell` summaries."""
    columns = list(dict.fromkeys(c.condition for c in cells))
    rows = list(dict.fromkeys((c.model, c.label) for c in cells))
    found = {(c.model, c.label, c.condition): c for c in cells}
    lines = [
        "| algorithm | model | " + " | ".join(columns) + " |",
        "|---|---|" + "---|" * len(columns),
    ]
    for model, label in rows:
        text = [_grid_cell(found.get((model, label, cond)), fmt) for cond in columns]
        lines.append(f"| {label} | {model} | " + " | ".join(text) + " |")
    return lines


def _grid_cell(cell, fmt) -> str:
    if cell is None:
        return "-"
    return fmt(cell.weight_error) + (f" ({cell.failures} failed)" if cell.failures else "")


def paper_lines(cells: Sequence, fmt, model: str = DEFAULT_MODEL) -> list[str]:
    """Per paper condition, the paper's finding beside each algorithm's weight error on the
    paper's model (and how often the penalised weight came out largest); the hardest
    condition of each algorithm in bold."""
    mine = [c for c in cells if c.model == model and c.condition in PAPER_FINDINGS]
    labels = list(dict.fromkeys(c.label for c in mine))
    found = {(c.label, c.condition): c for c in mine}
    hardest = {
        label: max(
            (c for c in mine if c.label == label and math.isfinite(c.weight_error)),
            key=lambda c: c.weight_error,
            default=None,
        )
        for label in labels
    }
    lines = [
        "| condition | the paper | " + " | ".join(labels) + " |",
        "|---|---|" + "---|" * len(labels),
    ]
    for condition, finding in PAPER_FINDINGS.items():
        text = []
        for label in labels:
            c = found.get((label, condition))
            if c is None:
                text.append("-")
                continue
            value = fmt(c.weight_error)
            value = f"**{value}**" if c is hardest[label] else value
            text.append(value + (f"; largest {c.largest_recovered}/{c.largest_checked}" if c.largest_checked else ""))
        lines.append(f"| {condition} | {finding} | " + " | ".join(text) + " |")
    return lines


def _order(value: float) -> float:
    return value if math.isfinite(value) else math.inf
