"""Weight-floor ablation (docs/ioc.md): the distractor condition at 0.27, 4 weight sets, seed 0,
for log-barrier and analytic-center with their own floor and with each other's.

    python studies/weight_floor.py --out docs/data/weight_floor   # ~4 min on 2 cores
    python studies/weight_floor.py --out docs/data/weight_floor --table
"""

from __future__ import annotations

import argparse
from pathlib import Path

from ioc_bench.runner.results import load_results
from ioc_bench.runner.run import run_cases
from ioc_bench.synthetic.suites import Suite
from ioc_bench.weights import WEIGHT_SETS

SUITE = Suite("weight-floor", "distractor, 4 weight sets, seed 0", tuple(WEIGHT_SETS), ("distractor",))
#: (algorithm, config): each algorithm with its default floor and with the other's.
RUNS = (
    ("log-barrier", {}),
    ("log-barrier", {"lower": 0.0}),
    ("analytic-center", {}),
    ("analytic-center", {"lower": 0.001}),
)


def table(out: Path) -> str:
    rows = ["| algorithm | floor | " + " | ".join(WEIGHT_SETS) + " | mean |", "|---|---|" + "---|" * 5]
    results = load_results(out)
    for algorithm in dict(RUNS):
        for floor in sorted({r.config["lower"] for r in results if r.algorithm == algorithm}):
            errs = {
                r.weight_set: r.weight_error for r in results if r.algorithm == algorithm and r.config["lower"] == floor
            }
            cells = " | ".join(f"{errs[w]:.4f}" for w in WEIGHT_SETS)
            rows.append(f"| {algorithm} | {floor:g} | {cells} | {sum(errs.values()) / len(errs):.4f} |")
    return "\n".join(rows)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--out", type=Path, default=Path("docs/data/weight_floor"))
    ap.add_argument("--table", action="store_true", help="only print the table of the results in --out")
    args = ap.parse_args()
    if not args.table:
        run_cases([s for algorithm, cfg in RUNS for s in SUITE.cases(algorithm, cfg)], args.out)
    print(table(args.out))


if __name__ == "__main__":
    main()
