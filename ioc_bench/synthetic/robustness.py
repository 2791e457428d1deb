"""Robustness curves: weight error against the severity of each perturbation, and their area.

The paper measures each perturbation at one size; users choosing a method need to know how
fast it degrades. For every algorithm (and config) and robustness axis (noise, leg-mass
error, speed error; :data:`~ioc_bench.synthetic.conditions.AXES`), the curve is the mean weight
error at each severity (``ideal`` is severity 0 on every axis), with a 95 % bootstrap
interval over the cases at that severity. The one-number summary of an axis is the area
under its curve divided by the severity range it spans: the mean weight error over the
range. An algorithm's robustness AUC is the mean of its axes' (complete axes only).
"""

from __future__ import annotations

from collections import defaultdict
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from ioc_bench.synthetic.case import CaseResult
from ioc_bench.synthetic.conditions import AXES, axis_conditions, get_condition
from ioc_bench.synthetic.results import run_label
from ioc_bench.synthetic.statistics import bootstrap_mean_ci
from ioc_bench.synthetic.suites import get_suite


@dataclass(frozen=True)
class Curve:
    """Weight error along one axis for one row (algorithm with its config).

    Attributes:
        label: the row.
        axis: the axis.
        severity: (n,) severities, percent, ascending.
        mean: (n,) mean weight error at each severity (failed cases left out).
        low, high: (n,) its 95 % bootstrap interval over the cases at that severity.
        cases: (n,) how many cases each point has.
        complete: every condition of the axis has at least one successful case.
        coverage: (n,) share of the successful cases with a 95 % weight region whose region
            holds the truth (NaN where no case reports one).
    """

    label: str
    axis: str
    severity: np.ndarray
    mean: np.ndarray
    low: np.ndarray
    high: np.ndarray
    cases: np.ndarray
    complete: bool
    coverage: np.ndarray

    @property
    def auc(self) -> float:
        """Mean weight error over the severity range (area under the curve / range)."""
        ok = np.isfinite(self.mean)
        if ok.sum() < 2:
            return float("nan")
        s, m = self.severity[ok], self.mean[ok]
        return float(np.trapezoid(m, s) / (s[-1] - s[0]))


#: A curve needs this many severities (ideal included): two points are just a condition.
MIN_POINTS = 3


def curves(results: Sequence[CaseResult]) -> list[Curve]:
    """Every (row, axis) curve the results have points for (at least :data:`MIN_POINTS`),
    over the ``robustness`` suite's design only (its weight sets and seeds), so that every
    point, the ideal one included, holds the same cases."""
    design = get_suite("robustness")
    by: dict[tuple[str, str], list[CaseResult]] = defaultdict(list)
    for r in results:
        if r.weight_set in design.weight_sets and r.seed in design.seeds:
            by[(run_label(r), r.condition)].append(r)
    out = []
    for label in sorted({k[0] for k in by}):
        for axis in AXES:
            conds = axis_conditions(axis)
            points = [(c, [r for r in by.get((label, c.name), []) if not r.failed]) for c in conds]
            present = [(c, rs) for c, rs in points if (label, c.name) in by]
            if len(present) < MIN_POINTS:
                continue
            errors = [[r.weight_error for r in rs] for _, rs in present]
            cis = [bootstrap_mean_ci(e) for e in errors]
            out.append(
                Curve(
                    label=label,
                    axis=axis,
                    severity=np.array([c.severity for c, _ in present], dtype=float),
                    mean=np.array([np.mean(e) if e else np.nan for e in errors]),
                    low=np.array([ci[0] if ci else np.nan for ci in cis]),
                    high=np.array([ci[1] if ci else np.nan for ci in cis]),
                    cases=np.array([len(e) for e in errors]),
                    complete=len(present) == len(conds) and all(rs for _, rs in present),
                    coverage=np.array([_coverage(rs) for _, rs in present]),
                )
            )
    return out


def _coverage(results: Sequence[CaseResult]) -> float:
    with_region = [r for r in results if r.covered is not None]
    return float(np.mean([r.covered for r in with_region])) if with_region else float("nan")


def auc_table(results: Sequence[CaseResult]) -> dict[str, dict[str, float]]:
    """Row -> {axis: AUC, ..., "mean": mean over complete axes} for rows with complete axes."""
    table: dict[str, dict[str, float]] = defaultdict(dict)
    for curve in curves(results):
        if curve.complete:
            table[curve.label][curve.axis] = curve.auc
    for row in table.values():
        row["mean"] = float(np.mean([row[a] for a in AXES if a in row]))
    return dict(table)


def is_robustness_condition(name: str) -> bool:
    return bool(get_condition(name).axis) or name == "ideal"
