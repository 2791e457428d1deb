"""The benchmark's eight demonstrations: gait figures, and Table I beside the paper's.

The demonstrations are the ones every suite uses (15 starts, multi-start seed 0, verified
as local minima), read from the cache or solved:

    python studies/demonstrations.py            # Markdown tables on stdout
    python studies/demonstrations.py --save DIR # also writes DIR/<weights>_<speed>.npz
"""

from __future__ import annotations

import argparse
from pathlib import Path

from ioc_bench.features import COST_FEATURES, TIME_UNIT
from ioc_bench.synthetic.demos import demonstration
from ioc_bench.table1 import PENALISES
from ioc_bench.task import FAST_SPEED, NOMINAL_SPEED, Task
from ioc_bench.weights import WEIGHT_SETS, parse_weights

#: The paper's Table I (its own model; weight set -> (hip, knee, dtau)).
PAPER_TABLE1 = {
    "nominal": (0.0975, 0.0809, 0.0142),
    "penalize-hip": (0.0360, 0.204, 0.0351),
    "penalize-knee": (0.192, 0.0331, 0.0206),
    "penalize-dtau": (0.112, 0.0897, 0.00307),
}


def demos() -> dict[tuple[str, float], object]:
    return {
        (name, speed): demonstration(parse_weights(name), task=Task(speed))
        for speed in (NOMINAL_SPEED, FAST_SPEED)
        for name in WEIGHT_SETS
    }


def gait_table(found: dict) -> str:
    lines = [
        "| weights | speed | step (L) | duration | step, 0.9 m leg | cadence (steps/min) | max / mid-swing foot "
        "height (L) | peak torque (m g L) | active bounds (physical) | artificial | local minimum (polished by) |",
        "|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for (name, speed), d in found.items():
        g, check = d.gait, d.local_minimum
        physical = ", ".join(f"{k} {v}" for k, v in g.active["physical"].items()) or "-"
        artificial = ", ".join(f"{k} {v}" for k, v in g.active["artificial"].items()) or "none"
        verdict = f"{'yes' if check.passed else 'NO'} ({check.polished_by:.2%})"
        lines.append(
            f"| {name} | {speed} | {g.step_length:.3f} | {g.duration:.2f} | {g.step_length_m:.2f} m | "
            f"{g.cadence:.0f} | {g.max_clearance:.4f} / {g.mid_swing_clearance:.4f} | "
            f"{max(g.peak_torques.values()):.3f} | {physical} | {artificial} | {verdict} |"
        )
    return "\n".join(lines)


def table1(found: dict, speed: float) -> str:
    """Per-step sums in the paper's units (feature x step duration in s) beside the paper."""
    lines = [
        f"Speed {speed}. Each cell: the step's per-step sum (the paper's Table I form, SI units of a 1 m, 1 kg "
        "walker) / the paper's value = ratio; the benchmark's feature (per unit time) in brackets. Bold: lowest "
        "in its row.",
        "",
        "| feature | " + " | ".join(WEIGHT_SETS) + " | lowest in its own set |",
        "|---|" + "---|" * (len(WEIGHT_SETS) + 1),
    ]
    own = {f: n for n, f in PENALISES.items()}
    for i, feature in enumerate(COST_FEATURES):
        sums = {
            n: found[(n, speed)].features[feature] * found[(n, speed)].trajectory.duration * TIME_UNIT
            for n in WEIGHT_SETS
        }
        low = min(sums, key=sums.get)
        cells = []
        for n in WEIGHT_SETS:
            paper = PAPER_TABLE1[n][i]
            text = f"{sums[n]:.3g} / {paper:.3g} = {sums[n] / paper:.2f} [{found[(n, speed)].features[feature]:.3g}]"
            cells.append(f"**{text}**" if n == low else text)
        mark = "yes" if low == own[feature] else f"NO (lowest: {low})"
        lines.append(f"| phi_{feature} | " + " | ".join(cells) + f" | {mark} |")
    return "\n".join(lines)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--save", type=Path, help="also save every demonstration here")
    args = ap.parse_args()
    found = demos()
    if args.save:
        for (name, speed), d in found.items():
            d.save(args.save / f"{name}_{speed}.npz")
    print(gait_table(found), "", table1(found, NOMINAL_SPEED), "", table1(found, FAST_SPEED), sep="\n")


if __name__ == "__main__":
    main()
