"""``ioc-bench run``: run a benchmark suite (default: smoke, log-barrier) and print its leaderboard.

Finished cases are written one file each, at once and atomically; running the same
command again resumes, skipping finished cases.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from ioc_bench.cli.common import UsageError, add_json_flag, json_object, positive_float, positive_int, print_json


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("run", help="run a benchmark suite and print its leaderboard", description=__doc__)
    p.add_argument("--suite", default="smoke", help="suite name (default smoke; see --list)")
    p.add_argument("--algorithm", default="log-barrier", help="registered algorithm (default log-barrier)")
    p.add_argument("--config", type=json_object, default={}, help="algorithm config overrides as JSON")
    p.add_argument("--out", type=Path, default=Path("results"), help="results directory (default results/)")
    p.add_argument("--workers", type=positive_int, default=None, help="parallel cases (default: all cores)")
    p.add_argument("--executor", choices=("local", "ray"), default="local", help="local processes or a Ray cluster")
    p.add_argument("--address", default=None, help="Ray cluster address (default: start a local Ray)")
    p.add_argument("--time-limit", type=positive_float, default=1800.0, help="seconds per case (default 1800)")
    p.add_argument("--list", action="store_true", help="list the suites and exit")
    add_json_flag(p)
    p.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    from ioc_bench.bench.leaderboard import markdown, summarise
    from ioc_bench.bench.results import load_results
    from ioc_bench.bench.runner import run_cases
    from ioc_bench.bench.suites import SUITES, get_suite
    from ioc_bench.cli.common import progress_bar
    from ioc_bench.ioc.registry import AlgorithmError, get_algorithm

    if args.list:
        for suite in SUITES.values():
            n = len(suite.weight_sets) * len(suite.conditions) * len(suite.seeds)
            print(f"{suite.name:<14} {n:3d} cases  {suite.description}")
        return 0
    try:
        suite = get_suite(args.suite)
        get_algorithm(args.algorithm)
    except (AlgorithmError, ValueError) as exc:
        raise UsageError(str(exc)) from None
    if args.executor == "ray":
        _require_ray()
    specs = suite.cases(args.algorithm, args.config)
    say = (lambda msg: print(msg, file=sys.stderr)) if not args.json else (lambda msg: None)
    say(f"suite {suite.name}: {len(specs)} cases of {args.algorithm} -> {args.out}/")
    failures = [0]
    with progress_bar(len(specs), "cases", enabled=not args.json) as bar:

        def on_case(spec, result) -> None:
            failures[0] += result.failed
            bar.update(1)
            bar.set_postfix(failures=failures[0])
            mark = f"FAILED ({result.reason})" if result.failed else f"weight error {result.weight_error:.4f}"
            if not args.json:
                bar.write(f"  {spec.key}: {mark}, {result.wall_time:.0f} s", file=sys.stderr)

        try:
            summary = run_cases(
                specs, args.out, args.workers, args.time_limit, args.executor, args.address, on_case, say
            )
        except KeyboardInterrupt:
            print(
                f"\ninterrupted; finished cases are in {args.out}/ - rerun the same command to resume", file=sys.stderr
            )
            return 130
    results = [r for r in load_results(args.out) if r.algorithm == args.algorithm]
    keys = {(s.weight_set, s.condition, s.seed) for s in specs}
    results = [r for r in results if (r.weight_set, r.condition, r.seed) in keys]
    if args.json:
        print_json({"summary": summary.__dict__, "cells": [c.__dict__ for c in summarise(results)]})
    else:
        say(f"{summary.ran} run, {summary.skipped} already done, {summary.failed} failed, {summary.wall_time:.0f} s")
        print(markdown(results, str(args.out)))
    return 0


def _require_ray() -> None:
    try:
        import ray  # noqa: F401
    except ImportError:
        raise UsageError("--executor ray needs Ray: pip install 'ioc-bench[ray]'") from None
