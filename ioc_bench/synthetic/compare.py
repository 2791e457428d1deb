"""Two runs compared cell by cell: what ``ioc-bench compare A B`` reports.

A user iterating on an algorithm runs a suite, changes something, runs it again and asks
what changed. Each run is its records (``ioc-bench compare`` reads them from two results
folders, as the leaderboard does: :func:`ioc_bench.cli.compare.compare_folders`). Cases are
paired by their identity: algorithm, model, cost basis, weight set, condition and seed, and
the config too, unless an algorithm has exactly one config in each run (then its cases pair
across the two configs: comparing a new config with the old one is what ``compare`` is for).
Pairs are grouped in the board's cells (model, algorithm with its config, condition:
:func:`~ioc_bench.synthetic.board.row_condition`) and every score the board averages
(:data:`SCORES`) is compared over the pairs in which both cases succeeded: the mean of B - A
with a percentile-bootstrap interval over the pairs
(:func:`~ioc_bench.synthetic.statistics.bootstrap_mean_ci`, seeded, the pairs being the
units: paired differences are what a re-run changes).

A score's verdict, lower being better for every one: ``better`` or ``worse`` when its
interval excludes 0 and the mean difference exceeds the score's tolerance (numerical noise
of re-solving the same case: :attr:`Score.tolerance`); ``no difference`` otherwise; ``n/a``
with fewer than two pairs (one pair has no interval, and no verdict at any level is drawn
from it; its difference is still reported). A cell's verdict is its weight error's, the
board's headline. Cases whose status changed (solved in one run, failed in the other, or
another status), and cases in only one run, are listed apart: they have no difference.

Other tracks' records (the human track's) are not compared (they are counted as skipped):
their headline is not a weight error (the human track's: a prediction error over several speeds).
"""

from __future__ import annotations

import math
from collections import defaultdict
from collections.abc import Callable, Sequence
from dataclasses import asdict, dataclass, field
from typing import Any

import numpy as np

from ioc_bench.model.catalogue import MODELS
from ioc_bench.runner.protocol import Record
from ioc_bench.synthetic.board import row_condition
from ioc_bench.synthetic.case import CaseResult
from ioc_bench.synthetic.conditions import CONDITIONS
from ioc_bench.synthetic.results import recorded_spec, result_config, run_label
from ioc_bench.synthetic.statistics import RESAMPLES, bootstrap_mean_ci

#: The verdicts a score or a cell can have.
BETTER, WORSE, SAME, NA = "better", "worse", "no difference", "n/a"
#: The score a cell's verdict is drawn from (the board's headline).
HEADLINE = "weight_error"
#: Seed of every bootstrap (the same comparison prints the same intervals).
SEED = 0


@dataclass(frozen=True)
class Score:
    """A per-case score the board averages (its :class:`~ioc_bench.synthetic.board.Cell` field
    ``name``), lower being better, and the smallest difference that counts.

    A difference of means within ``absolute + relative * mean |A|`` is numerical noise (two
    runs of the same deterministic case re-solve the same optima to the solver's tolerance),
    whatever its interval says.
    """

    name: str
    label: str
    value: Callable[[CaseResult], float | None]
    absolute: float = 0.0
    relative: float = 0.0

    def tolerance(self, a_values: Sequence[float]) -> float:
        """The smallest mean difference that counts, given A's values of the pairs."""
        scale = float(np.mean(np.abs(a_values))) if len(a_values) else 0.0
        return self.absolute + self.relative * scale


def _transfer(key: str) -> Callable[[CaseResult], float | None]:
    def value(r: CaseResult) -> float | None:
        t = r.transfer or {}
        return t.get(key) if isinstance(t.get(key), (int, float)) else None

    return value


#: The compared scores, the headline first. Tolerances: the board prints weight errors to 4
#: decimals (1e-4 is below what it shows); trajectory errors of a perfect fit are some 4e-11
#: (the solver's tolerance), so differences under 1e-8 or 0.1 % are noise; time and solves
#: are measured, not re-solved: every difference counts.
SCORES: tuple[Score, ...] = (
    Score("weight_error", "weight error", lambda r: r.weight_error, absolute=1e-4),
    Score("trajectory_error", "trajectory error", lambda r: r.trajectory_error, absolute=1e-8, relative=1e-3),
    Score(
        "found_trajectory_error",
        "found trajectory error",
        lambda r: r.found_trajectory_error,
        absolute=1e-8,
        relative=1e-3,
    ),
    Score("transfer_error", "transfer trajectory error", _transfer("trajectory_error"), absolute=1e-8, relative=1e-3),
    Score("transfer_excess", "transfer excess cost", _transfer("excess_cost"), absolute=1e-8, relative=1e-3),
    Score("wall_time", "time (s)", lambda r: r.wall_time),
    Score("forward_solves", "forward solves", lambda r: float(r.n_solves)),
)


@dataclass(frozen=True)
class Difference:
    """One score of one cell: the mean of B - A over the ``pairs`` in which both cases have it.

    ``interval`` is None with fewer than two pairs; ``mean_a`` and ``mean_b`` are the two
    runs' means over those same pairs.
    """

    score: str
    pairs: int
    mean_a: float
    mean_b: float
    difference: float
    interval: tuple[float, float] | None
    tolerance: float
    verdict: str


@dataclass(frozen=True)
class StatusChange:
    """A paired case whose status differs between the runs (``failed`` is a status)."""

    case: str
    cell: str
    status_a: str
    status_b: str
    reason_a: str
    reason_b: str

    @property
    def kind(self) -> str:
        """``now fails``, ``now solved`` or ``other status``."""
        failed_a, failed_b = self.status_a == "failed", self.status_b == "failed"
        return (
            "now fails" if failed_b and not failed_a else "now solved" if failed_a and not failed_b else "other status"
        )


@dataclass(frozen=True)
class CellComparison:
    """One board cell (model, algorithm with its config, condition) of both runs.

    ``label`` names the row: the board's label when both runs used one config, else
    ``algorithm [A's config -> B's config]``. ``cases_a``/``failures_a`` (and B's) count
    each run's cases in the cell; ``paired`` how many are in both; ``only_a``/``only_b``
    name the others.
    """

    model: str
    algorithm: str
    label: str
    condition: str
    config_a: dict[str, Any] | None
    config_b: dict[str, Any] | None
    cases_a: int
    cases_b: int
    failures_a: int
    failures_b: int
    paired: int
    only_a: tuple[str, ...]
    only_b: tuple[str, ...]
    differences: tuple[Difference, ...]
    status_changes: tuple[StatusChange, ...]

    @property
    def verdict(self) -> str:
        """The headline score's verdict."""
        return self.difference(HEADLINE).verdict

    def difference(self, score: str) -> Difference:
        return next(d for d in self.differences if d.score == score)

    @property
    def name(self) -> str:
        """How lists name the cell: ``model / label / condition``."""
        return f"{self.model} / {self.label} / {self.condition}"


@dataclass(frozen=True)
class Comparison:
    """Run B against run A, cell by cell (:func:`compare_results`)."""

    a: str
    b: str
    level: float
    cells: tuple[CellComparison, ...]
    skipped_a: int = 0
    skipped_b: int = 0
    resamples: int = RESAMPLES
    seed: int = SEED
    tolerances: dict[str, dict[str, float]] = field(default_factory=dict)

    @property
    def paired(self) -> int:
        return sum(c.paired for c in self.cells)

    @property
    def status_changes(self) -> list[StatusChange]:
        return [s for c in self.cells for s in c.status_changes]

    def to_dict(self) -> dict[str, Any]:
        """The comparison as JSON values: every cell with its verdict and differences, the
        status changes and the unpaired cases."""
        cells = []
        for c in self.cells:
            data = asdict(c)
            data["verdict"] = c.verdict
            data["differences"] = {d.score: {k: v for k, v in asdict(d).items() if k != "score"} for d in c.differences}
            data["status_changes"] = [asdict(s) | {"kind": s.kind} for s in c.status_changes]
            cells.append(data)
        return {
            "a": self.a,
            "b": self.b,
            "level": self.level,
            "resamples": self.resamples,
            "seed": self.seed,
            "headline": HEADLINE,
            "tolerances": self.tolerances,
            "paired": self.paired,
            "skipped_human_records": {"a": self.skipped_a, "b": self.skipped_b},
            "verdicts": {v: sum(c.verdict == v for c in self.cells) for v in (BETTER, WORSE, SAME, NA)},
            "cells": cells,
            "status_changes": [asdict(s) | {"kind": s.kind} for s in self.status_changes],
            "only_a": [k for c in self.cells for k in c.only_a],
            "only_b": [k for c in self.cells for k in c.only_b],
        }


def compare_results(
    a: Sequence[Record], b: Sequence[Record], level: float = 0.95, name_a: str = "A", name_b: str = "B"
) -> Comparison:
    """Run ``b`` against run ``a``, cell by cell (see the module's docstring).

    Raises ``ValueError`` if ``level`` is not in (0, 1), if either run holds no synthetic
    case, or if the two have no case in common.
    """
    if not (isinstance(level, float | int) and 0 < level < 1):
        raise ValueError(f"the interval's level must be a number between 0 and 1, got {level!r}")
    (syn_a, others_a), (syn_b, others_b) = _split(a), _split(b)
    for name, syn, others in ((name_a, syn_a, others_a), (name_b, syn_b, others_b)):
        if not syn:
            raise ValueError(
                f"no synthetic-track case in {name} ({len(others)} record(s) of other tracks: compare reads the "
                "synthetic track only)"
            )
    across = _paired_across_configs(syn_a, syn_b)
    keyed_a, keyed_b = _keyed(syn_a, across, name_a), _keyed(syn_b, across, name_b)
    if not keyed_a.keys() & keyed_b.keys():
        raise ValueError(
            f"{name_a} and {name_b} have no case in common ({name_a}: {_holds(syn_a)}; {name_b}: {_holds(syn_b)}; "
            "cases pair by algorithm, model, cost basis, weight set, condition, seed and config)"
        )
    cells: dict[tuple[str, str, str, str], dict[str, list]] = defaultdict(lambda: {"pairs": [], "a": [], "b": []})
    # In a fixed order: the bootstrap draws its resamples by position, so the same folders must give the
    # same order whatever the order they were read in (or a set's hash order).
    for key in sorted(keyed_a.keys() | keyed_b.keys()):
        ra, rb = keyed_a.get(key), keyed_b.get(key)
        r = ra if ra is not None else rb
        assert r is not None
        group = r.algorithm if r.algorithm in across else run_label(r)  # across configs, the cell is the algorithm
        side = "pairs" if ra is not None and rb is not None else "a" if ra is not None else "b"
        cells[(r.model, group, row_condition(r), r.algorithm)][side].append((ra, rb))
    compared = [_compare_cell(cell, groups, level) for cell, groups in sorted(cells.items(), key=_cell_order)]
    tolerances = {s.name: {"absolute": s.absolute, "relative": s.relative} for s in SCORES}
    return Comparison(
        name_a, name_b, float(level), tuple(compared), len(others_a), len(others_b), tolerances=tolerances
    )


def _split(records: Sequence[Record]) -> tuple[list[CaseResult], list[Record]]:
    """The synthetic track's records and the others', each in the given order."""
    synthetic = [r for r in records if isinstance(r, CaseResult)]
    return synthetic, [r for r in records if not isinstance(r, CaseResult)]


def _holds(results: Sequence[CaseResult]) -> str:
    """``3 case(s) of log-barrier, bilevel [cfg 1234abcd]``: what a run holds, for messages."""
    labels = sorted({run_label(r) for r in results})
    more = f" and {len(labels) - 3} more" if len(labels) > 3 else ""
    return f"{len(results)} case(s) of {', '.join(labels[:3])}{more}"


def _paired_across_configs(a: Sequence[CaseResult], b: Sequence[CaseResult]) -> set[str]:
    """The algorithms with exactly one config in each run: their cases pair whatever the configs."""
    configs_a, configs_b = defaultdict(set), defaultdict(set)
    for results, configs in ((a, configs_a), (b, configs_b)):
        for r in results:
            configs[r.algorithm].add(run_label(r))
    return {alg for alg in configs_a.keys() & configs_b.keys() if len(configs_a[alg]) == len(configs_b[alg]) == 1}


def _keyed(results: Sequence[CaseResult], across: set[str], name: str) -> dict[tuple, CaseResult]:
    """``results`` by their pair key; ``ValueError`` if one case is there twice (never so in a folder)."""
    keyed: dict[tuple, CaseResult] = {}
    for r in results:
        key = _pair_key(r, across)
        if key in keyed:
            raise ValueError(f"{name} holds the case {_key(r)} twice")
        keyed[key] = r
    return keyed


def _pair_key(r: CaseResult, across: set[str]) -> tuple:
    """What pairs a case with its counterpart: its identity, without the config where the
    algorithm has one config in each run."""
    key = (r.algorithm, r.model, r.basis, r.weight_set, r.condition, r.seed)  # a basis is another truth
    return key if r.algorithm in across else (*key, run_label(r))


def _cell_order(item: tuple[tuple[str, str, str, str], Any]) -> tuple:
    model, label, condition, _ = item[0]
    order = {c: i for i, c in enumerate(CONDITIONS)}
    return (list(MODELS).index(model) if model in MODELS else 99, model, label, order.get(condition, 99), condition)


def _key(r: CaseResult) -> str:
    """The case's result-file key (``algorithm/weights__condition__seed<k>...``)."""
    return recorded_spec(r).key


def _compare_cell(cell: tuple[str, str, str, str], groups: dict[str, list], level: float) -> CellComparison:
    model, _group, condition, algorithm = cell
    pairs = groups["pairs"]
    in_a = [ra for ra, _ in pairs] + [ra for ra, _ in groups["a"]]
    in_b = [rb for _, rb in pairs] + [rb for _, rb in groups["b"]]
    config_a = result_config(in_a[0]) if in_a else None
    config_b = result_config(in_b[0]) if in_b else None
    if in_a and in_b and config_a != config_b:
        label = f"{algorithm} [{_config_name(in_a[0])} -> {_config_name(in_b[0])}]"
    else:
        label = run_label((in_a or in_b)[0])
    solved = [(ra, rb) for ra, rb in pairs if not ra.failed and not rb.failed]
    changes = tuple(
        StatusChange(_key(rb), f"{model} / {label} / {condition}", ra.status, rb.status, ra.reason, rb.reason)
        for ra, rb in sorted(pairs, key=lambda p: _key(p[1]))
        if ra.status != rb.status
    )
    return CellComparison(
        model=model,
        algorithm=algorithm,
        label=label,
        condition=condition,
        config_a=config_a,
        config_b=config_b,
        cases_a=len(in_a),
        cases_b=len(in_b),
        failures_a=sum(r.failed for r in in_a),
        failures_b=sum(r.failed for r in in_b),
        paired=len(pairs),
        only_a=tuple(sorted(_key(ra) for ra, _ in groups["a"])),
        only_b=tuple(sorted(_key(rb) for _, rb in groups["b"])),
        differences=tuple(_difference(score, solved, level) for score in SCORES),
        status_changes=changes,
    )


def _config_name(r: CaseResult) -> str:
    label = run_label(r)
    return label[len(r.algorithm) :].strip(" []") or "defaults"


def _difference(score: Score, pairs: Sequence[tuple[CaseResult, CaseResult]], level: float) -> Difference:
    """``score``'s mean B - A over the pairs in which both cases have it, its interval and verdict."""
    values = [(score.value(ra), score.value(rb)) for ra, rb in pairs]
    values = [(x, y) for x, y in values if _finite(x) and _finite(y)]
    a = np.array([x for x, _ in values], dtype=float)
    b = np.array([y for _, y in values], dtype=float)
    n = len(values)
    tolerance = score.tolerance(a)
    if n == 0:
        return Difference(score.name, 0, math.nan, math.nan, math.nan, None, tolerance, NA)
    diffs = b - a
    mean = float(diffs.mean())
    interval = bootstrap_mean_ci(diffs, seed=SEED, level=level)
    return Difference(
        score.name, n, float(a.mean()), float(b.mean()), mean, interval, tolerance, verdict(mean, interval, tolerance)
    )


def verdict(difference: float, interval: tuple[float, float] | None, tolerance: float) -> str:
    """``better``/``worse`` (lower is better) when ``interval`` excludes 0 and ``difference``
    exceeds ``tolerance``; ``no difference`` otherwise; ``n/a`` without an interval."""
    if interval is None or not math.isfinite(difference):
        return NA
    low, high = interval
    if low <= 0 <= high or abs(difference) <= tolerance:
        return SAME
    return WORSE if difference > 0 else BETTER


def _finite(value: Any) -> bool:
    return isinstance(value, (int, float)) and not isinstance(value, bool) and math.isfinite(value)
