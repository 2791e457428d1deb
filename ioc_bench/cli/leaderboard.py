"""``ioc-bench leaderboard``: regenerate the leaderboard (Markdown + JSON) from a results directory."""

from __future__ import annotations

import argparse
from pathlib import Path

from ioc_bench.cli.common import add_json_flag, path_arg, print_json, usage_errors


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("leaderboard", help="write the leaderboard from result files", description=__doc__)
    p.add_argument("results", type=path_arg, help="results directory (as written by `ioc-bench run`)")
    p.add_argument(
        "--out", type=path_arg, default=Path("leaderboards"), help="output directory (default leaderboards/)"
    )
    add_json_flag(p)
    p.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    from ioc_bench.bench.leaderboard import plan_leaderboard, summarise
    from ioc_bench.bench.results import select_results

    with usage_errors():  # every result and the output checked here, so that errors while writing stay real errors
        results = select_results(args.results)
        board = plan_leaderboard(results, args.out, source=str(args.results), out_name="--out")
    paths = board.write()
    if args.json:
        print_json({"files": [str(p) for p in paths], "cells": [c.__dict__ for c in summarise(results)]})
    else:
        print(paths[0].read_text())
        print(f"wrote {', '.join(str(p) for p in paths)}")
    return 0
