"""``ioc-bench leaderboard``: regenerate the leaderboard (Markdown + JSON) from a results directory."""

from __future__ import annotations

import argparse
from pathlib import Path

from ioc_bench.cli.common import (
    UsageError,
    add_json_flag,
    input_dir,
    output_dir,
    output_file,
    path_arg,
    print_json,
    usage_errors,
)


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("leaderboard", help="write the leaderboard from result files", description=__doc__)
    p.add_argument("results", type=path_arg, help="results directory (as written by `ioc-bench run`)")
    p.add_argument(
        "--out", type=path_arg, default=Path("leaderboards"), help="output directory (default leaderboards/)"
    )
    add_json_flag(p)
    p.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    from ioc_bench.bench.leaderboard import FILES, summarise, write_leaderboard
    from ioc_bench.bench.results import load_results, no_results_message

    input_dir(args.results)
    with usage_errors():
        results = load_results(args.results)
    if not results:
        raise UsageError(no_results_message(args.results))
    output_dir(args.out)
    for name in FILES:
        output_file(args.out / name)
    paths = write_leaderboard(results, args.out, source=str(args.results))
    if args.json:
        print_json({"files": [str(p) for p in paths], "cells": [c.__dict__ for c in summarise(results)]})
    else:
        print(paths[0].read_text())
        print(f"wrote {', '.join(str(p) for p in paths)}")
    return 0
