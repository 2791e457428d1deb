"""``ioc-bench figures``: the paper's Table I and Figures 4-6 from a directory of results."""

from __future__ import annotations

import argparse
from pathlib import Path

from ioc_bench.cli.common import add_json_flag, path_arg, print_json, usage_errors


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("figures", help="Table I and Figures 4-6 from benchmark results", description=__doc__)
    p.add_argument("results", type=path_arg, metavar="RESULTS_DIR", help="directory of case results (`ioc-bench run`)")
    p.add_argument("--out", type=path_arg, default=Path("figures"), help="output directory (default figures/)")
    p.add_argument(
        "--algorithm",
        action="append",
        metavar="NAME",
        help="only this algorithm (repeat for several; default: every algorithm in the results)",
    )
    add_json_flag(p)
    p.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    from ioc_bench.viz.figures import plan_figures

    with usage_errors():  # every result and output checked here, so that errors while drawing stay real errors
        plan = plan_figures(args.results, args.out, args.algorithm, out_name="--out")
    written = plan.draw()
    if args.json:
        print_json({name: str(path) for name, path in written.items()})
    else:
        width = max(len(name) for name in written)
        for name, path in written.items():
            print(f"{name:<{width}}  {path}")
    return 0
