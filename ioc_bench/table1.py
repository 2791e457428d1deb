"""The paper's Table I: features of the optimal step under each weight set.

Each penalised feature should be lowest in the column of the weight set that penalises
it. Optima are local, so after the multi-start every set is re-solved once more from the
other sets' optima (cross-seeding) and keeps whichever is cheaper under its own weights.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

from ioc_bench.demo import Demonstration
from ioc_bench.features import COST_FEATURES
from ioc_bench.optimize import optimize_gait
from ioc_bench.task import Task
from ioc_bench.weights import WEIGHT_SETS

#: Which feature each weight set penalises.
PENALISES = {"penalize-hip": "hip", "penalize-knee": "knee", "penalize-dtau": "dtau"}


@dataclass(frozen=True)
class FeatureTable:
    """Optimal demonstrations per weight set and the Table I pattern check."""

    demos: dict[str, Demonstration]

    def lowest(self, feature: str) -> str:
        """The weight set whose optimum has the lowest value of ``feature``."""
        return min(self.demos, key=lambda name: self.demos[name].features[feature])

    @property
    def pattern(self) -> dict[str, bool]:
        """For each penalised feature: is it lowest under the set that penalises it?"""
        return {feature: self.lowest(feature) == name for name, feature in PENALISES.items()}

    def markdown(self) -> str:
        names = list(self.demos)
        lines = [
            "| feature | " + " | ".join(names) + " | lowest in its own set |",
            "|---" * (len(names) + 2) + "|",
        ]
        own = {f: n for n, f in PENALISES.items()}
        for feature in COST_FEATURES:
            low = self.lowest(feature)
            cells = [
                f"**{self.demos[n].features[feature]:.3e}**" if n == low else f"{self.demos[n].features[feature]:.3e}"
                for n in names
            ]
            mark = "yes" if low == own[feature] else f"NO (lowest: {low})"
            lines.append(f"| phi_{feature} | " + " | ".join(cells) + f" | {mark} |")
        return "\n".join(lines)


def feature_table(
    task: Task,
    starts: int = 15,
    seed: int = 0,
    cross_seed: bool = True,
    workers: int | None = None,
    on_progress: Callable[[str], None] | None = None,
) -> FeatureTable:
    """Solve every weight set of :data:`WEIGHT_SETS` for ``task``."""
    demos: dict[str, Demonstration] = {}
    for name in WEIGHT_SETS:
        demos[name] = optimize_gait(name, task=task, starts=starts, seed=seed, workers=workers)
        if on_progress:
            on_progress(name)
    if cross_seed:
        demos = {name: _reseed(name, demos, task, workers) for name in demos}
        if on_progress:
            on_progress("cross-seeding")
    return FeatureTable(demos)


def _reseed(name: str, demos: dict[str, Demonstration], task: Task, workers: int | None) -> Demonstration:
    """Re-solve ``name`` from the other sets' optima; keep the cheaper feasible optimum."""
    others = [d for n, d in demos.items() if n != name]
    again = optimize_gait(name, task=task, starts=1, guesses=others, workers=workers)
    best = demos[name]
    if again.solver.success and (not best.solver.success or again.solver.objective < best.solver.objective):
        return again
    return best
