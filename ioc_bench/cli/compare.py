"""``ioc-bench compare A B``: run B against run A, cell by cell: each score's difference with an
interval, the cases whose status changed, and a verdict per cell (better, worse, no difference)."""

from __future__ import annotations

import argparse
import math
import os
from pathlib import Path
from typing import TYPE_CHECKING

from ioc_bench.cli.common import UsageError, add_json_flag, path_arg, print_json, usage_errors

if TYPE_CHECKING:
    from ioc_bench.synthetic.compare import Comparison, Difference

#: How many unpaired cases the text report names per run (the JSON names every one).
SHOWN_UNPAIRED = 10


def level_arg(text: str) -> float:
    """An argparse type: an interval's level, a number strictly between 0 and 1."""
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a number, got {text!r}") from None
    if not 0 < value < 1:  # NaN fails this too
        raise argparse.ArgumentTypeError(f"must be a number between 0 and 1 (0.95 is 95 %), got {text!r}")
    return value


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("compare", help="compare two runs' results, cell by cell", description=__doc__)
    p.add_argument("a", type=path_arg, metavar="A", help="the reference results folder (`ioc-bench run --out`)")
    p.add_argument("b", type=path_arg, metavar="B", help="the results folder compared with it (differences are B - A)")
    p.add_argument("--level", type=level_arg, default=0.95, help="the intervals' level (default 0.95)")
    add_json_flag(p)
    p.set_defaults(run=run)


def compare_folders(a: str | os.PathLike, b: str | os.PathLike, level: float = 0.95) -> Comparison:
    """Compare the results folders ``a`` and ``b``
    (:func:`~ioc_bench.synthetic.compare.compare_results`); ``ValueError`` (one line) for a folder
    that cannot be read, a result file that does not read
    (:class:`~ioc_bench.runner.results.ResultFileError`, naming it), a folder without results,
    or no case in common."""
    from ioc_bench.runner.results import select_results
    from ioc_bench.synthetic.compare import compare_results

    return compare_results(select_results(a), select_results(b), level, str(a), str(b))


def run(args: argparse.Namespace) -> int:
    for path in (args.a, args.b):
        if _is_file(path):  # not a folder: say what compare reads (a board's leaderboard.json is not read back)
            raise UsageError(f"{path} is a file: compare reads two results folders, as `ioc-bench run --out` writes")
    with usage_errors():
        comparison = compare_folders(args.a, args.b, args.level)
    if args.json:
        print_json(comparison.to_dict())
    else:
        print(report(comparison))
    return 0


def _is_file(path: Path) -> bool:
    """Whether ``path`` is a regular file (anything else, unreadable included, is left to the folder check)."""
    try:
        return path.is_file()
    except (OSError, ValueError):
        return False


def report(comparison: Comparison) -> str:
    """The comparison as text: a header, one row per cell, the status changes, the unpaired cases."""
    from ioc_bench.synthetic.compare import BETTER, HEADLINE, RESAMPLES, SCORES, WORSE

    c = comparison
    pct = f"{100 * c.level:g} %"
    tolerance = next(s for s in SCORES if s.name == HEADLINE).absolute
    lines = [
        f"compare {c.a} (A) -> {c.b} (B): {c.paired} paired case(s) in {len(c.cells)} cell(s); differences are B - A, "
        f"lower is better",
        f"{pct} intervals: bootstrap over the pairs solved in both ({RESAMPLES} resamples, seed {c.seed}); verdict: "
        f"better/worse if the weight error's interval excludes 0 and |B - A| > {tolerance:g}, n/a under 2 pairs",
        "",
    ]
    header = (
        "model",
        "algorithm",
        "condition",
        "paired",
        "weight error A -> B",
        f"B - A [{pct} interval]",
        "verdict",
        "trajectory error B - A",
        "time (s) A -> B",
        "failures A -> B",
        "only A / B",
    )
    rows = [header]
    for cell in c.cells:
        w, t, s = (cell.difference(name) for name in (HEADLINE, "trajectory_error", "wall_time"))
        rows.append(
            (
                cell.model,
                cell.label,
                cell.condition,
                str(cell.paired),
                f"{_f(w.mean_a)} -> {_f(w.mean_b)}" if w.pairs else "-",
                _interval(w),
                cell.verdict,
                f"{_sci(t.difference)} ({t.verdict})" if t.pairs else "-",
                f"{_f(s.mean_a, 1)} -> {_f(s.mean_b, 1)}" if s.pairs else "-",
                f"{cell.failures_a} -> {cell.failures_b}",
                f"{len(cell.only_a)} / {len(cell.only_b)}",
            )
        )
    widths = [max(len(row[i]) for row in rows) for i in range(len(header))]
    lines += ["  ".join(v.ljust(wd) for v, wd in zip(row, widths)).rstrip() for row in rows]
    differ = [f"{cell.name} ({cell.verdict})" for cell in c.cells if cell.verdict in (BETTER, WORSE)]
    lines += ["", f"cells that differ ({len(differ)}): {', '.join(differ)}" if differ else "cells that differ: none"]
    changes = c.status_changes
    lines.append(f"status changes ({len(changes)}):" if changes else "status changes: none")
    for s in changes:
        why = (
            f" ({s.reason_b})" if s.status_b == "failed" else f" (was: {s.reason_a})" if s.status_a == "failed" else ""
        )
        lines.append(f"  {s.kind}: {s.case}: {s.status_a} -> {s.status_b}{why}")
    for side, name in (("only_a", f"only in A ({c.a})"), ("only_b", f"only in B ({c.b})")):
        keys = [k for cell in c.cells for k in getattr(cell, side)]
        if keys:
            more = f", and {len(keys) - SHOWN_UNPAIRED} more" if len(keys) > SHOWN_UNPAIRED else ""
            lines.append(f"{name}, {len(keys)} case(s): {', '.join(keys[:SHOWN_UNPAIRED])}{more}")
    skipped = [f"{n} in {side}" for n, side in ((c.skipped_a, "A"), (c.skipped_b, "B")) if n]
    if skipped:
        lines.append(f"human-track records not compared: {', '.join(skipped)}")
    return "\n".join(lines)


def _interval(d: Difference) -> str:
    """``+0.0012 [+0.0003, +0.0021]``, ``+0.0012 (no interval: 1 case)``, or ``-`` without a pair."""
    if not d.pairs:
        return "-"
    if d.interval is None:
        return f"{d.difference:+.4f} (no interval: 1 case)"
    low, high = d.interval
    return f"{d.difference:+.4f} [{low:+.4f}, {high:+.4f}]"


def _f(value: float, digits: int = 4) -> str:
    return "n/a" if not math.isfinite(value) else f"{value:.{digits}f}"


def _sci(value: float) -> str:
    return "n/a" if not math.isfinite(value) else f"{value:+.2e}"
