"""Where a suite's time goes, per algorithm, from the result files of a run.

    python benchmarks/suite_profile.py RESULTS_DIR [--suite paper]

For every algorithm: cases, the median and total of the algorithm's own time and of the
scoring after it, and per oracle (``optimize`` forward solves, ``project`` projections,
``sensitivity`` KKT solves, ``derivatives``, the weight or KKT fits) the calls and seconds per
case and their share of the algorithm's time. Every figure comes from what each case
recorded (``oracle`` calls and seconds, ``wall_time``, ``scoring_time``).
"""

from __future__ import annotations

import argparse
import statistics
from collections import defaultdict

from ioc_bench.runner.results import load_results
from ioc_bench.synthetic.suites import get_suite


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("results")
    parser.add_argument("--suite", default=None, help="only the cases of this suite's design")
    args = parser.parse_args()
    results = load_results(args.results)
    if args.suite:
        suite = get_suite(args.suite)
        keep = {(w, c, s) for w in suite.weight_sets for c in suite.conditions for s in suite.seeds}
        results = [r for r in results if (r.weight_set, r.condition, r.seed) in keep and r.model == suite.model]
    by = defaultdict(list)
    for r in results:
        by[r.algorithm].append(r)
    columns = ["algorithm", "cases", "time per case: median / total (s)", "scoring: median / total (s)"]
    columns.append("oracle: calls and s per case (share of the time)")
    print("| " + " | ".join(columns) + " |")
    print("|---|---|---|---|---|")
    for algo, rs in sorted(by.items()):
        wall = [r.wall_time for r in rs]
        scoring = [r.scoring_time for r in rs]
        calls, seconds = defaultdict(float), defaultdict(float)
        for r in rs:
            for k, v in r.oracle.get("calls", {}).items():
                calls[k] += v / len(rs)
            for k, v in r.oracle.get("seconds", {}).items():
                seconds[k] += v / len(rs)
        mean_wall = sum(wall) / len(rs)
        parts = ", ".join(
            f"{k} {calls[k]:.1f} x, {seconds[k]:.2f} s ({seconds[k] / mean_wall:.0%})"
            for k in sorted(calls, key=lambda k: -seconds[k])
        )
        print(
            f"| {algo} | {len(rs)} | {statistics.median(wall):.1f} / {sum(wall):.0f} | "
            f"{statistics.median(scoring):.1f} / {sum(scoring):.0f} | {parts} |"
        )


if __name__ == "__main__":
    main()
