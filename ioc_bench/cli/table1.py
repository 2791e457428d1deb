"""``ioc-bench table1``: the paper's Table I (features of each weight set's optimum) in Markdown."""

from __future__ import annotations

import argparse

from ioc_bench.cli.common import add_json_flag, add_multistart_args, print_json, solver_dict
from ioc_bench.task import NOMINAL_SPEED


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("table1", help="features of the four weight sets' optima (Table I)", description=__doc__)
    add_multistart_args(p, NOMINAL_SPEED)
    p.add_argument("--no-cross-seed", action="store_true", help="do not re-solve each set from the others' optima")
    add_json_flag(p)
    p.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    import sys

    from ioc_bench.table1 import feature_table
    from ioc_bench.task import Task

    def progress(name: str) -> None:
        if not args.json:
            print(f"  solved {name}", file=sys.stderr)

    table = feature_table(
        Task(args.speed), args.starts, args.seed, not args.no_cross_seed, args.workers, on_progress=progress
    )
    feasible = all(d.solver.success for d in table.demos.values())
    if args.json:
        print_json(
            {
                "speed": args.speed,
                "features": {n: d.features for n, d in table.demos.items()},
                "solver": {n: solver_dict(d.solver) for n, d in table.demos.items()},
                "pattern": table.pattern,
                "all_feasible": feasible,
            }
        )
    else:
        print(f"Table I at speed {args.speed:g} ({args.starts} starts per set, seed {args.seed}):\n")
        print(table.markdown())
        print()
        for name, demo in table.demos.items():
            s = demo.solver
            print(f"- {name}: {s.status}, max violation {s.max_violation:.1e}, {s.iterations} iterations")
        verdict = "holds" if all(table.pattern.values()) else "DOES NOT hold"
        print(f"\nPattern (each penalised feature lowest in its own set) {verdict}.")
    return 0 if feasible and all(table.pattern.values()) else 1
