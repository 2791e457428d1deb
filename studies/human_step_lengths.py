"""Which step lengths the walker's optima take over the effort weights, at a person's speed
(docs/notes/2026-12-07-human-committed-run.md, "What the speed-only task shows"): for each
shipped subject at one speed, the subject's walker given the speed only, solved (3 seeded
starts, the cheapest kept) for every weight direction of a simplex lattice over (hip, knee,
dtau); its step length against the person's, and its leg-angle RMSE.

    python studies/human_step_lengths.py --speed T05 --divisions 4   # ~3 min on 1 core
"""

from __future__ import annotations

import argparse
import itertools

import numpy as np

from ioc_bench.human import load_step
from ioc_bench.human.scoring import solve_step
from ioc_bench.human.suites import SHIPPED_SUBJECTS
from ioc_bench.task import Task


def lattice(divisions: int) -> list[tuple[int, ...]]:
    """The simplex lattice points (integers summing to ``divisions``) over three weights."""
    return [w for w in itertools.product(range(divisions + 1), repeat=3) if sum(w) == divisions]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--speed", default="T05", help="speed code (default T05)")
    parser.add_argument("--divisions", type=int, default=4, help="lattice divisions (default 4: 15 directions)")
    args = parser.parse_args()
    print(
        "| subject | person's step length (L) | weights (hip, knee, dtau) | walker's step length | |log| error "
        "| angle RMSE (deg) |"
    )
    print("|---|---|---|---|---|---|")
    for subject in SHIPPED_SUBJECTS:
        step = load_step(subject, args.speed)
        rows = []
        for w in lattice(args.divisions):
            solved = solve_step(np.array(w, dtype=float), step, 3, 0, "lattice", task=Task(step.task.speed))
            error = abs(np.log(solved.step_length / step.task.step_length)) if solved.success else np.nan
            rows.append((w, solved.step_length, error, solved.rmse_deg(step)))
        for w, length, error, rmse in sorted(rows, key=lambda r: -r[1] if np.isfinite(r[1]) else 0):
            print(f"| {subject} | {step.task.step_length:.3f} | {w} | {length:.3f} | {error:.3f} | {rmse:.1f} |")


if __name__ == "__main__":
    main()
