"""One row per algorithm of a human-track run, every design of a person's own steps pooled
(docs/human.md, "The committed run"): the change of gait with speed and the step length,
beside the angles. The board (``ioc-bench leaderboard``) gives the same sums per design.

    python studies/human_run_summary.py results-human/ [--times times.txt]

``--times`` names a file of ``ALGORITHM SECONDS s`` lines (each algorithm's wall time).
"""

from __future__ import annotations

import argparse
import math

import numpy as np

from ioc_bench.human.record import HumanResult
from ioc_bench.human.summary import pooled_r2
from ioc_bench.runner.results import select_results


def _finite(values) -> list[float]:
    return [v for v in values if v is not None and math.isfinite(v)]


def row(algorithm: str, records: list[HumanResult], seconds: float | None) -> str:
    """The algorithm's cells: pooled over the predictions of a person's own steps (a copy
    exists), step length over every prediction, the one-speed design's angles."""
    preds = [s for r in records for s in r.predictions()]
    own = [s for s in preds if s.copy_from]
    carried = [s for s in preds if s.continued_from]
    one = [s for r in records if r.design == "one speed" for s in r.predictions()]
    change = pooled_r2([(s.adaptation_deg, s.copy_adaptation_deg) for s in own])
    cold = pooled_r2([(s.cold_adaptation_deg, s.copy_adaptation_deg) for s in own])
    beat_copy = sum(s.adaptation_deg < s.copy_adaptation_deg for s in own if math.isfinite(s.adaptation_deg))
    beat_pop = sum(s.adaptation_deg < s.population_adaptation_deg for s in own if math.isfinite(s.adaptation_deg))
    level = np.median(_finite([s.step_length_error for s in preds]))
    scaled = np.median(_finite([s.step_length_change_error for s in own]))
    families = sum(s.family_changed is True for s in carried), sum(s.family_changed is not None for s in carried)
    minutes = "-" if seconds is None else f"{seconds / 60:.1f}"
    angles = np.mean(_finite([s.rmse_deg for s in one]))
    nominal = np.mean(_finite([s.nominal_rmse_deg for s in one]))
    cells = [
        f"`{algorithm}`", minutes, f"{sum(r.failed for r in records)} of {len(records)}", f"{change:.2f} ({cold:.2f})",
        f"{beat_copy} of {len(own)}", f"{beat_pop} of {len(own)}", f"{level:.3f} ({scaled:.3f})",
        f"{families[0]} of {families[1]}",
        f"{angles:.2f} ({nominal:.2f})", f"{sum(s.beats_nominal is True for s in preds)} of {len(preds)}",
        f"{sum(s.beats_copy is True for s in own)} of {len(own)}",
    ]  # fmt: skip
    return "| " + " | ".join(cells) + " |"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("results", help="a results folder of human cases")
    parser.add_argument("--times", help="a file of 'ALGORITHM SECONDS s' lines")
    args = parser.parse_args()
    times = {}
    if args.times:
        with open(args.times) as lines:
            for line in lines:
                name, seconds, *_ = line.split()
                times[name] = float(seconds)
    records = [r for r in select_results(args.results) if isinstance(r, HumanResult)]
    print(
        "| algorithm | wall time (min) | failed | change R^2 (cold) | change beats copy | change beats population "
        "| step length: level (change) | family changes | one speed: prediction RMSE (nominal) | beat nominal "
        "| beat copy |"
    )
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for algorithm in sorted({r.algorithm for r in records}):
        mine = [r for r in records if r.algorithm == algorithm]
        print(row(algorithm, mine, times.get(algorithm)))


if __name__ == "__main__":
    main()
