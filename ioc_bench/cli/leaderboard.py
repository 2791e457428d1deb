"""``ioc-bench leaderboard``: regenerate the leaderboard (Markdown + JSON) from a results directory."""

from __future__ import annotations

import argparse

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
    out_help = "output directory (default: the results directory itself; a board already there is replaced)"
    p.add_argument("--out", type=path_arg, default=None, help=out_help)
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
    out = args.results if args.out is None else args.out
    output_dir(out)
    for name in FILES:
        output_file(out / name)
    replaced = [str(out / name) for name in FILES if (out / name).is_file()]
    paths = write_leaderboard(results, out, source=str(args.results))
    if args.json:
        files = [str(p) for p in paths]
        print_json({"files": files, "replaced": replaced, "cells": [c.__dict__ for c in summarise(results)]})
    else:
        print(paths[0].read_text())
        print(f"wrote {', '.join(str(p) for p in paths)}" + (f" (replacing {', '.join(replaced)})" if replaced else ""))
    return 0
