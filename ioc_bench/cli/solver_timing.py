"""``ioc-bench solver-timing``: median solve times of the trajectory optimizer (cold, warm-started, 15-start)."""

from __future__ import annotations

import argparse
import os
import sys

from ioc_bench.cli.common import add_json_flag, positive_int, print_json

#: What a solve should take on a 2-core machine, in seconds; each median is printed against its target.
TARGETS = {"cold_median_s": 2.0, "warm_median_s": 0.5, "multistart_median_s": 15.0}


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("solver-timing", help="time the trajectory optimizer (prints medians)", description=__doc__)
    p.add_argument("--repeats", type=positive_int, default=7, help="cold and warm solves to time (default 7)")
    p.add_argument("--multistart-repeats", type=positive_int, default=3, help="15-start solves to time (default 3)")
    add_json_flag(p)
    p.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    from ioc_bench.solver_timing import time_solver

    def say(msg: str) -> None:
        if not args.json:
            print(f"  {msg}", file=sys.stderr)

    result = time_solver(args.repeats, args.multistart_repeats, on_progress=say).to_dict()
    result["cores"] = os.cpu_count()
    if args.json:
        print_json(result)
        return 0
    print(f"gait solver, {result['n_intervals']} Hermite-Simpson intervals, {result['cores']} cores")
    print(f"  build (once per process)   {result['build_s']:.2f} s")
    rows = [
        ("cold single-start solve", "cold_median_s", f"{result['cold_median_iterations']:.0f} iterations"),
        ("warm-started solve", "warm_median_s", f"{result['warm_median_iterations']:.0f} iterations"),
        ("15-start solve, all cores", "multistart_median_s", f"{result['multistart_repeats']} repeats"),
    ]
    for label, key, extra in rows:
        verdict = "ok" if result[key] < TARGETS[key] else "OVER TARGET"
        print(f"  {label:<26} {result[key]:.3f} s median ({extra}; target < {TARGETS[key]:g} s: {verdict})")
    if result["failures"]:
        print(f"  {result['failures']} of the timed solves did not converge")
    return 0
