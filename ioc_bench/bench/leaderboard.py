"""The leaderboard: algorithm x condition summaries, regenerated from result files only.

Never edit the written files by hand: ``ioc-bench leaderboard results/ --out leaderboards/``
rewrites ``README.md`` (Markdown) and ``leaderboard.json`` from the results. With 3 or more
seeds per case a 95 % bootstrap confidence interval of the mean weight error is given.
"""

from __future__ import annotations

import datetime
import importlib.metadata
import os
import platform
from collections import defaultdict
from collections.abc import Sequence
from dataclasses import asdict, dataclass
from pathlib import Path

import numpy as np

from ioc_bench.bench.case import CaseResult
from ioc_bench.bench.conditions import CONDITIONS
from ioc_bench.fileio import atomic_write_json, atomic_write_text

#: Minimum seeds per case for a bootstrap confidence interval.
MIN_SEEDS_FOR_CI = 3
#: The paper's findings, one per condition (Rebula et al. 2019, section III).
PAPER_FINDINGS = {
    "ideal": "weight error < 1 %",
    "ideal-fast": "weight error < 1 %",
    "noise": "penalised weight recovered as the largest; lowest weight error of the perturbed conditions",
    "mass": "penalised weight recovered as the largest",
    "speed": "penalised weight recovered as the largest",
    "distractor": "the hardest: largest weight error (weight attributed to distractors)",
}


@dataclass(frozen=True)
class Cell:
    """Summary of one algorithm under one condition."""

    algorithm: str
    condition: str
    cases: int
    failures: int
    seeds: tuple[int, ...]
    weight_error: float
    weight_error_ci: tuple[float, float] | None
    trajectory_error: float
    wall_time: float
    forward_solves: float
    largest_recovered: int
    largest_checked: int


def _mean(values: Sequence[float]) -> float:
    arr = np.asarray([v for v in values if np.isfinite(v)], dtype=float)
    return float(arr.mean()) if arr.size else float("nan")


def _ci(values: Sequence[float], seed: int = 0) -> tuple[float, float] | None:
    from scipy.stats import bootstrap

    arr = np.asarray([v for v in values if np.isfinite(v)], dtype=float)
    if arr.size < 2 or np.ptp(arr) == 0:
        return (float(arr.mean()), float(arr.mean())) if arr.size else None
    res = bootstrap((arr,), np.mean, confidence_level=0.95, n_resamples=9999, rng=np.random.default_rng(seed))
    return float(res.confidence_interval.low), float(res.confidence_interval.high)


def penalised_is_largest(result: CaseResult) -> bool | None:
    """For a penalize-* case: is the penalised feature's estimated weight the largest?"""
    if not result.weight_set.startswith("penalize-") or result.failed:
        return None
    feature = result.weight_set.removeprefix("penalize-")
    if feature not in result.features:
        return None
    return int(np.argmax(result.weights)) == result.features.index(feature)


def summarise(results: Sequence[CaseResult]) -> list[Cell]:
    """One :class:`Cell` per (algorithm, condition), conditions in catalogue order."""
    groups: dict[tuple[str, str], list[CaseResult]] = defaultdict(list)
    for r in results:
        groups[(r.algorithm, r.condition)].append(r)
    order = {c: i for i, c in enumerate(CONDITIONS)}
    cells = []
    for (algo, cond), rs in sorted(groups.items(), key=lambda kv: (kv[0][0], order.get(kv[0][1], 99), kv[0][1])):
        ok = [r for r in rs if not r.failed]
        seeds_per_case = defaultdict(set)
        for r in rs:
            seeds_per_case[r.weight_set].add(r.seed)
        enough = min(len(s) for s in seeds_per_case.values()) >= MIN_SEEDS_FOR_CI
        checks = [c for c in (penalised_is_largest(r) for r in rs) if c is not None]
        cells.append(
            Cell(
                algorithm=algo,
                condition=cond,
                cases=len(rs),
                failures=len(rs) - len(ok),
                seeds=tuple(sorted({r.seed for r in rs})),
                weight_error=_mean([r.weight_error for r in ok]),
                weight_error_ci=_ci([r.weight_error for r in ok]) if enough else None,
                trajectory_error=_mean([r.trajectory_error for r in ok]),
                wall_time=_mean([r.wall_time for r in rs]),
                forward_solves=_mean([r.n_solves for r in rs]),
                largest_recovered=sum(checks),
                largest_checked=len(checks),
            )
        )
    return cells


def versions() -> dict[str, str]:
    out = {"python": platform.python_version(), "platform": platform.platform(terse=True)}
    for pkg in ("ioc-bench", "casadi", "numpy", "scipy", "mujoco", "gymnasium"):
        try:
            out[pkg] = importlib.metadata.version(pkg)
        except importlib.metadata.PackageNotFoundError:
            out[pkg] = "not installed"
    return out


def _fmt(x: float, digits: int = 4) -> str:
    return "n/a" if not np.isfinite(x) else f"{x:.{digits}f}"


def _sci(x: float) -> str:
    return "n/a" if not np.isfinite(x) else f"{x:.3g}"


def markdown(results: Sequence[CaseResult], source: str = "results/") -> str:
    """The leaderboard as Markdown (header, summary table, paper comparison, every case)."""
    cells = summarise(results)
    seeds = sorted({r.seed for r in results})
    v = versions()
    lines = [
        "# ioc-bench leaderboard",
        "",
        f"Generated by `ioc-bench leaderboard {source}` on {datetime.date.today().isoformat()}; "
        "regenerated from the result files, never edited by hand.",
        "",
        "**Method.** Each case runs one IOC algorithm on one demonstrated step: the best of 15 starts of the "
        "trajectory optimizer for the true weights (multi-start seed 0), observed as the condition allows "
        "(noise, wrong model, wrong task, distractor features; SPEC section 4). "
        "Weight error: mean |estimated - true| of the unit-norm weights over the features the IOC weighed. "
        "Trajectory error: sum over knots and segments of squared angle and angular-velocity differences between "
        "the estimated weights' optimal step (in the observation's basin) and the observed step. "
        "Time and forward solves are the algorithm's own (scoring excluded). Failed cases count in *failures* "
        "and are left out of the means.",
        "",
        f"**Seeds:** {', '.join(map(str, seeds))} (per case: algorithm randomness and observation noise). "
        + (
            "95 % bootstrap confidence intervals (scipy.stats.bootstrap, 9999 resamples) where every case has "
            f"{MIN_SEEDS_FOR_CI}+ seeds."
            if any(c.weight_error_ci for c in cells)
            else f"No confidence intervals: they need {MIN_SEEDS_FOR_CI}+ seeds per case; "
            "this is a single run, so small differences are not significant."
        ),
        "",
        "**Versions:** " + ", ".join(f"{k} {val}" for k, val in v.items()),
        "",
        "| algorithm | condition | cases | weight error | 95 % CI | trajectory error | time (s) | forward solves "
        "| penalised weight largest | failures |",
        "|---|---|---|---|---|---|---|---|---|---|",
    ]
    for c in cells:
        ci = "" if c.weight_error_ci is None else f"[{_fmt(c.weight_error_ci[0])}, {_fmt(c.weight_error_ci[1])}]"
        largest = f"{c.largest_recovered}/{c.largest_checked}" if c.largest_checked else "-"
        lines.append(
            f"| {c.algorithm} | {c.condition} | {c.cases} | {_fmt(c.weight_error)} | {ci} | "
            f"{_sci(c.trajectory_error)} | {c.wall_time:.1f} | {c.forward_solves:.1f} | {largest} | {c.failures} |"
        )
    lines += ["", *_paper_comparison(cells), "", *_case_table(results)]
    return "\n".join(lines) + "\n"


def _paper_comparison(cells: Sequence[Cell]) -> list[str]:
    lines = [
        "## Against the paper's findings",
        "",
        "| algorithm | condition | paper | here |",
        "|---|---|---|---|",
    ]
    by_algo: dict[str, list[Cell]] = defaultdict(list)
    for c in cells:
        by_algo[c.algorithm].append(c)
    for algo, cs in by_algo.items():
        worst = max((c for c in cs if np.isfinite(c.weight_error)), key=lambda c: c.weight_error, default=None)
        for c in cs:
            here = f"weight error {_fmt(c.weight_error)}"
            if c.largest_checked:
                here += f"; penalised weight largest in {c.largest_recovered}/{c.largest_checked} cases"
            if worst is not None and c is worst:
                here += "; the hardest condition here"
            lines.append(f"| {algo} | {c.condition} | {PAPER_FINDINGS.get(c.condition, '-')} | {here} |")
    return lines


def _case_table(results: Sequence[CaseResult]) -> list[str]:
    lines = [
        "## Every case",
        "",
        "| algorithm | weight set | condition | seed | status | estimated weights (features) | weight error "
        "| trajectory error | time (s) | solves |",
        "|---|---|---|---|---|---|---|---|---|---|",
    ]
    order = {c: i for i, c in enumerate(CONDITIONS)}
    for r in sorted(results, key=lambda r: (r.algorithm, order.get(r.condition, 99), r.weight_set, r.seed)):
        w = ", ".join(f"{x:.3f}" for x in r.weights) if not r.failed else r.reason
        lines.append(
            f"| {r.algorithm} | {r.weight_set} | {r.condition} | {r.seed} | {r.status} | {w} ({', '.join(r.features)}) "
            f"| {_fmt(r.weight_error)} | {_sci(r.trajectory_error)} | {r.wall_time:.1f} | {r.n_solves} |"
        )
    return lines


def write_leaderboard(results: Sequence[CaseResult], out: str | os.PathLike, source: str = "results/") -> list[Path]:
    """Write ``README.md`` and ``leaderboard.json`` into ``out``; returns their paths."""
    if not results:
        raise ValueError("no case results to summarise")
    out = Path(out)
    md = atomic_write_text(out / "README.md", markdown(results, source))
    data = {
        "generated_by": f"ioc-bench leaderboard {source}",
        "versions": versions(),
        "seeds": sorted({r.seed for r in results}),
        "cells": [asdict(c) for c in summarise(results)],
        "cases": [{k: v for k, v in r.to_dict().items() if k not in ("history", "oracle")} for r in results],
    }
    js = atomic_write_json(out / "leaderboard.json", data)
    return [md, js]
