"""Is penalize-hip's low phi_hip (0.14x the paper's Table I) a matter of step length?

Held step lengths 0.35, 0.5 and 0.6 L at speed 0.27, 4 starts each, penalize-hip beside
nominal; per-step sums in the paper's units (docs/gait_regime.md, "Table I beside the
paper's"). About 2 minutes on one core.

    python studies/penalize_hip_lengths.py
"""

from __future__ import annotations

from ioc_bench.features import COST_FEATURES, TIME_UNIT
from ioc_bench.optimize import optimize_gait
from ioc_bench.task import Task


def main() -> None:
    print("| weights | held step (L) | per-step hip / knee / dtau |")
    print("|---|---|---|")
    for length in (0.35, 0.5, 0.6):
        for weights in ("penalize-hip", "nominal"):
            d = optimize_gait(weights, task=Task(0.27, step_length=length), starts=4, workers=1, verify=False)
            sums = [d.features[f] * d.trajectory.duration * TIME_UNIT for f in COST_FEATURES]
            status = "" if d.solver.success else f" ({d.solver.status})"
            print(f"| {weights} | {length} | {' / '.join(f'{s:.3g}' for s in sums)}{status} |")


if __name__ == "__main__":
    main()
