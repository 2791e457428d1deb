"""The paper's Table I: features of the optimal step under each weight set.

Each penalised feature should be lowest in the column of the weight set that penalises
it. Optima are local, so after the multi-start every set is re-solved once more from the
other sets' optima (cross-seeding) and keeps whichever is cheaper under its own weights.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass

from ioc_bench.demo import Demonstration
from ioc_bench.features import COST_FEATURES
from ioc_bench.optimize import optimize_gait
from ioc_bench.task import Task
from ioc_bench.weights import WEIGHT_SETS, penalised_feature

#: Which feature each of the walker's weight sets penalises (``penalised_feature`` of each).
PENALISES = {name: penalised_feature(name) for name in WEIGHT_SETS if penalised_feature(name)}


FeatureValues = Mapping[str, Mapping[str, float]]


@dataclass(frozen=True)
class FeatureTable:
    """Optimal demonstrations per weight set and the Table I pattern check."""

    demos: dict[str, Demonstration]

    @property
    def features(self) -> dict[str, dict[str, float]]:
        return {name: dict(d.features) for name, d in self.demos.items()}

    def lowest(self, feature: str) -> str:
        """The weight set whose optimum has the lowest value of ``feature``."""
        return lowest(self.features, feature)

    @property
    def pattern(self) -> dict[str, bool]:
        """For each penalised feature: is it lowest under the set that penalises it?"""
        return {feature: verdict == "yes" for feature, verdict in verdicts(self.features).items()}

    def markdown(self) -> str:
        return markdown_table(self.features)


def lowest(values: FeatureValues, feature: str) -> str:
    """The weight set (key of ``values``) with the lowest value of ``feature``."""
    return min(values, key=lambda name: values[name][feature])


def verdicts(values: FeatureValues) -> dict[str, str]:
    """Per penalised feature: ``yes``, ``NO (lowest: <set>)``, or ``n/a (...)`` when it cannot be checked."""
    names = list(values)
    out = {}
    for name, feature in PENALISES.items():
        if name not in names:
            out[feature] = f"n/a ({name} absent)"
        elif len(names) < 2:
            out[feature] = "n/a (one set only)"
        else:
            low = lowest(values, feature)
            out[feature] = "yes" if low == name else f"NO (lowest: {low})"
    return out


def markdown_table(values: FeatureValues) -> str:
    """Table I in Markdown: rows the effort features, columns the weight sets of ``values``.

    The lowest value of each row is bold; the last column is :func:`verdicts`.
    """
    names = list(values)
    verdict = verdicts(values)
    lines = [
        "| feature | " + " | ".join(names) + " | lowest in its own set |",
        "|---" * (len(names) + 2) + "|",
    ]
    for feature in COST_FEATURES:
        low = lowest(values, feature)
        cells = [_cell(values[n][feature], bold=n == low) for n in names]
        lines.append(f"| phi_{feature} | " + " | ".join(cells) + f" | {verdict.get(feature, '-')} |")
    return "\n".join(lines)


def pattern_summary(values: FeatureValues) -> str:
    """One line: does the pattern hold, over the features that can be checked?"""
    checked = [v for v in verdicts(values).values() if not v.startswith("n/a")]
    if not checked:
        return "Pattern not checkable: no penalising set with something to compare to."
    held = sum(v == "yes" for v in checked)
    word = "holds" if held == len(checked) else "DOES NOT hold"
    return f"Pattern (each penalised feature lowest in its own set) {word}: {held} of {len(checked)} features."


def _cell(value: float, bold: bool) -> str:
    return f"**{value:.3e}**" if bold else f"{value:.3e}"


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
