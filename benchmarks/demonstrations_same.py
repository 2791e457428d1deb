"""Solve a suite's demonstrations afresh and compare them with a saved run of another commit.

A change to the trajectory optimizer (its formulation, scaling, starts or options) may
change how fast the demonstrations are found, never which ones: every demonstration of
the benchmark must come out the same. This solves each demonstration a suite observes
(without the cache), saves what it found, and with ``--against`` prints side by side
per demonstration the multi-start's iterations (median and total over its starts) and
seconds, and how far the chosen optimum moved:

- ``angles``: the largest change of a segment angle at any knot, relative to the angle's
  range over the step;
- ``features``: the largest relative change of a cost feature;
- ``verified``: whether each run's optimum passed the local-minimum check.

Usage (the second run on the changed commit)::

    python benchmarks/demonstrations_same.py --save /tmp/before.json
    python benchmarks/demonstrations_same.py --save /tmp/after.json --against /tmp/before.json

``--suite`` picks the suite (default ``ideal``: the four weight sets at both speeds, the
eight demonstrations every walker case observes). Run it on a quiet machine: the seconds
depend on what else runs.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import tempfile
import time
from pathlib import Path

import numpy as np

from ioc_bench.demo import Demonstration
from ioc_bench.synthetic.suites import get_suite


def solve_all(suite_name: str, workers: int | None) -> dict[str, dict]:
    """Every demonstration the suite's cases observe, solved without the cache."""
    suite = get_suite(suite_name)
    requests = {}
    for spec in suite.cases("bilevel"):
        for request in spec.demo_requests():
            label = f"{spec.weight_set} @ {request.task.speed:g}"
            requests.setdefault(label, request)
    out = {}
    for label, request in requests.items():
        t0 = time.perf_counter()
        demo = request.solve(workers)
        out[label] = _record(demo, time.perf_counter() - t0)
        print(f"{label}: {out[label]['iterations_total']} iterations, {out[label]['seconds']:.1f} s", flush=True)
    return out


def _record(demo: Demonstration, seconds: float) -> dict:
    its = [s.report.iterations for s in demo.multistart.starts] if demo.multistart else [demo.solver.iterations]
    return {
        "angles": demo.trajectory.q[:, :, 2].tolist(),
        "features": dict(demo.features),
        "objective": demo.solver.objective,
        "success": demo.solver.success,
        "verified": bool(demo.local_minimum and demo.local_minimum.passed),
        "iterations_median": float(statistics.median(its)),
        "iterations_total": int(sum(its)),
        "seconds": seconds,
    }


def compare(before: dict[str, dict], after: dict[str, dict]) -> list[str]:
    """Markdown rows: per demonstration, iterations, seconds and how far the optimum moved."""
    rows = [
        "| demonstration | iterations per start: median before / after | total before / after | s before / after "
        "| angles moved (of range) | features moved (relative) | verified before / after |",
        "|---|---|---|---|---|---|---|",
    ]
    for label, b in before.items():
        a = after.get(label)
        if a is None:
            rows.append(f"| {label} | not solved after | | | | | |")
            continue
        qb, qa = np.asarray(b["angles"]), np.asarray(a["angles"])
        span = np.maximum(np.ptp(qb, axis=0), 1e-12)
        angles = float(np.max(np.abs(qa - qb) / span)) if qa.shape == qb.shape else float("inf")
        feats = max(abs(a["features"][f] - v) / max(abs(v), 1e-12) for f, v in b["features"].items())
        rows.append(
            f"| {label} | {b['iterations_median']:g} / {a['iterations_median']:g} "
            f"| {b['iterations_total']} / {a['iterations_total']} | {b['seconds']:.1f} / {a['seconds']:.1f} "
            f"| {angles:.1e} | {feats:.1e} | {_yes(b['verified'])} / {_yes(a['verified'])} |"
        )
    return rows


def _yes(flag: bool) -> str:
    return "yes" if flag else "no"


def _save(path: Path, data: dict) -> None:
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=path.name, suffix=".tmp")
    with os.fdopen(fd, "w") as f:
        json.dump(data, f)
    os.replace(tmp, path)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--suite", default="ideal", help="suite whose demonstrations are solved (default ideal)")
    parser.add_argument("--save", type=Path, required=True, help="JSON file to write this run to")
    parser.add_argument("--against", type=Path, help="a saved run to compare with")
    parser.add_argument("--workers", type=int, default=None, help="multi-start processes (default: all cores)")
    args = parser.parse_args()
    if not args.save.parent.is_dir():
        parser.error(f"--save {args.save}: folder {args.save.parent} does not exist")
    try:
        before = json.loads(args.against.read_text()) if args.against else None
    except (OSError, ValueError) as exc:
        parser.error(f"--against {args.against}: cannot be read as a saved run ({exc})")
    if before is not None and not isinstance(before, dict):
        parser.error(f"--against {args.against}: not a saved run (expected a JSON object)")
    after = solve_all(args.suite, args.workers)
    _save(args.save, after)
    if before is not None:
        print("\n".join(compare(before, after)))


if __name__ == "__main__":
    main()
