"""The paper's Table I and Figures 4-6, drawn from a directory of case results.

Everything here reads finished :class:`~ioc_bench.synthetic.case.CaseResult` records and
never runs an optimization, so the figures of any algorithm (or of several side by side)
can be remade at will from ``ioc-bench run`` output. Results of one algorithm with
different configs are drawn as different algorithms (``name__cfg<digest>``, as their
result files are named), never pooled:

- Table I: features of each weight set's demonstration (ideal and ideal-fast speeds).
- Figure 4: per algorithm, the ideal condition's convergence for every weight set.
- Figure 5: per algorithm, the four imperfect conditions x weight sets.
- Figure 6: weight error and trajectory error per condition, all algorithms together.
"""

from __future__ import annotations

import os
from collections.abc import Iterable, Sequence
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np
from matplotlib.lines import Line2D
from matplotlib.patches import Patch
from matplotlib.ticker import MaxNLocator

from ioc_bench.features import ALL_FEATURES, COST_FEATURES
from ioc_bench.fileio import atomic_write_text
from ioc_bench.paths import PathError, check_file_name, check_output_dir, check_output_file
from ioc_bench.plotting import plt, save_figure
from ioc_bench.runner.results import select_results
from ioc_bench.synthetic.case import CaseResult
from ioc_bench.synthetic.conditions import AXES, CONDITIONS
from ioc_bench.synthetic.results import run_slug
from ioc_bench.synthetic.robustness import curves as robustness_curves
from ioc_bench.table1 import markdown_table, pattern_summary
from ioc_bench.viz.common import FEATURE_COLORS
from ioc_bench.viz.convergence import draw_convergence
from ioc_bench.weights import WEIGHT_SETS

#: Conditions whose demonstrations Table I tabulates (one table each).
TABLE1_CONDITIONS: tuple[str, ...] = ("ideal", "ideal-fast")
#: The imperfect conditions of Figure 5, in the order of its columns.
FIGURE5_CONDITIONS: tuple[str, ...] = ("distractor", "mass", "noise", "speed")
#: Prefix of the reason of a case whose demonstration itself failed (see ``run_case``).
#: Trajectory errors are drawn on a log axis; exact zeros are shown at this floor.
_LOG_FLOOR = 1e-12


# --------------------------------------------------------------------------- selection


def weight_set_order(names: Iterable[str]) -> list[str]:
    """The paper's four sets first (in their usual order), then custom sets sorted."""
    names = set(names)
    return [n for n in WEIGHT_SETS if n in names] + sorted(names - set(WEIGHT_SETS))


def condition_order(names: Iterable[str]) -> list[str]:
    """Conditions in the order of :data:`CONDITIONS`, then unknown ones sorted."""
    names = set(names)
    return [n for n in CONDITIONS if n in names] + sorted(names - set(CONDITIONS))


def pick_case(results: Sequence[CaseResult], algorithm: str, condition: str, weight_set: str) -> CaseResult | None:
    """The case to draw for one panel: the lowest seed present (``None`` if none)."""
    matches = [r for r in results if (r.algorithm, r.condition, r.weight_set) == (algorithm, condition, weight_set)]
    return min(matches, key=lambda r: r.seed, default=None)


# --------------------------------------------------------------------------- Table I


def table1_markdown(results: Sequence[CaseResult]) -> str:
    """Table I in Markdown: one table per demonstration speed present.

    Rows are the effort features, columns the paper's named weight sets found in the
    results; the lowest value of each row is bold, and the last column says whether the
    feature a set penalises is lowest under that set (the pattern the paper reports).
    """
    sections = [_table1_section(cond, demos) for cond in TABLE1_CONDITIONS if (demos := _table1_demos(results, cond))]
    head = "# Table I: features of the demonstrated steps\n\n"
    if not sections:
        return head + (
            "No Table I available: the results hold no ideal or ideal-fast case of a named weight set "
            f"({', '.join(WEIGHT_SETS)}) with demonstration features.\n"
        )
    return head + "\n\n".join(sections) + "\n"


def write_table1(results: Sequence[CaseResult], path: str | os.PathLike) -> Path:
    """Write :func:`table1_markdown` to ``path`` (atomically)."""
    return atomic_write_text(path, table1_markdown(results))


def _table1_demos(results: Sequence[CaseResult], condition: str) -> dict[str, CaseResult]:
    """One case per named weight set of ``condition`` whose demonstration was solved.

    Every algorithm and seed sees the same (cached) demonstration, so any usable case will
    do; a case the algorithm failed still carries a good demonstration.
    """
    usable = [
        r
        for r in results
        if r.condition == condition
        and r.weight_set in WEIGHT_SETS
        and all(f in r.demo_features for f in COST_FEATURES)  # empty for a failed demonstration
    ]
    first: dict[str, CaseResult] = {}
    for r in sorted(usable, key=lambda r: (r.failed, r.algorithm, r.seed)):
        first.setdefault(r.weight_set, r)
    return {name: first[name] for name in WEIGHT_SETS if name in first}


def _table1_section(condition: str, demos: dict[str, CaseResult]) -> str:
    """One speed's table (header, rows, and a one-line verdict on the pattern)."""
    values = {name: case.demo_features for name, case in demos.items()}
    speed = next(iter(demos.values())).demo_speed
    lines = [f"## Speed {speed:g} ({condition} condition)", "", markdown_table(values), "", pattern_summary(values)]
    missing = [n for n in WEIGHT_SETS if n not in demos]
    if missing:
        lines.append(f"Weight sets absent from the results: {', '.join(missing)}.")
    return "\n".join(lines)


# --------------------------------------------------------------------------- Figures 4 and 5


def plot_figure4(results: Sequence[CaseResult], algorithm: str, path: str | os.PathLike) -> Path:
    """Figure 4 for one algorithm: the ideal condition's convergence, one panel per weight set.

    Raises ``ValueError`` if the algorithm has no ideal case.
    """
    names = weight_set_order(r.weight_set for r in results if r.algorithm == algorithm and r.condition == "ideal")
    if not names:
        raise ValueError(f"no ideal-condition results for {algorithm!r}")
    ncols = min(2, len(names))
    nrows = -(-len(names) // ncols)
    fig, axes = plt.subplots(nrows, ncols, figsize=(6.5 * ncols, 3.6 * nrows), squeeze=False)
    cases = [pick_case(results, algorithm, "ideal", n) for n in names]
    for ax, name, case in zip(axes.flat, names, cases):
        _panel(ax, case, title=f"{name} weights")
    for ax in axes.flat[len(names) :]:
        ax.set_axis_off()
    drawn = [c for c in cases if c is not None]
    title = f"Figure 4: {algorithm}, ideal condition (seed {_seeds(drawn)}): candidate weights per iteration"
    _finish_grid(fig, drawn, title)
    return save_figure(fig, path)


def plot_figure5(results: Sequence[CaseResult], algorithm: str, path: str | os.PathLike) -> Path:
    """Figure 5 for one algorithm: columns are the imperfect conditions, rows the weight sets.

    A missing case leaves its panel blank with a note. Raises ``ValueError`` if the
    algorithm has no case in any of the four conditions.
    """
    mine = [r for r in results if r.algorithm == algorithm and r.condition in FIGURE5_CONDITIONS]
    names = weight_set_order(r.weight_set for r in mine)
    if not names:
        raise ValueError(f"no results for {algorithm!r} under {', '.join(FIGURE5_CONDITIONS)}")
    ncols = len(FIGURE5_CONDITIONS)
    fig, axes = plt.subplots(len(names), ncols, figsize=(4.6 * ncols, 3.0 * len(names)), squeeze=False)
    cases = []
    for i, name in enumerate(names):
        for j, cond in enumerate(FIGURE5_CONDITIONS):
            case = pick_case(mine, algorithm, cond, name)
            cases.append(case)
            _panel(axes[i, j], case, title="", missing=f"no {cond} result for {name}")
            _grid_labels(axes[i, j], row=name if j == 0 else None, col=cond if i == 0 else None)
    drawn = [c for c in cases if c is not None]
    _finish_grid(fig, drawn, f"Figure 5: {algorithm} under imperfect conditions (seed {_seeds(drawn)})")
    return save_figure(fig, path)


def _panel(ax, case: CaseResult | None, title: str, missing: str = "no result") -> None:
    """One convergence panel via ``draw_convergence``, or a blank panel saying why (``title``: its prefix)."""
    if case is None:
        _blank(ax, missing)
        return
    if not case.history:
        _blank(ax, f"{case.status}: no iterations recorded\n{_shorten(case.reason)}".strip())
    else:
        draw_convergence(ax, case, legend=False)
        ax.xaxis.set_major_locator(MaxNLocator(integer=True))
    ax.set_title(_panel_title(case, title), fontsize=9)


def _panel_title(case: CaseResult, prefix: str) -> str:
    """``weight error 1.2e-04 | traj. error 3.4e-06`` plus the status if not converged."""
    if case.failed:
        body = "FAILED"
    else:
        body = f"weight error {case.weight_error:.2g} | traj. error (re-solved) {case.trajectory_error:.2g}"
        if case.status != "converged":
            body += f" ({case.status})"
    return f"{prefix}: {body}" if prefix else body


def _blank(ax, text: str) -> None:
    ax.set_xticks([])
    ax.set_yticks([])
    for spine in ax.spines.values():
        spine.set_color("0.8")
    ax.text(0.5, 0.5, text, ha="center", va="center", fontsize=9, color="0.4", transform=ax.transAxes, wrap=True)


def _grid_labels(ax, row: str | None, col: str | None) -> None:
    """Row (weight set) and column (condition) headers of the Figure 5 grid."""
    if col:
        desc = CONDITIONS[col].description if col in CONDITIONS else ""
        ax.annotate(
            f"{col}\n{desc}",
            (0.5, 1.22),
            xycoords="axes fraction",
            ha="center",
            va="bottom",
            fontsize=10,
            fontweight="bold",
        )
    if row:
        ax.annotate(
            row,
            (-0.32, 0.5),
            xycoords="axes fraction",
            ha="right",
            va="center",
            rotation=90,
            fontsize=11,
            fontweight="bold",
        )


def _finish_grid(fig, cases: Sequence[CaseResult], title: str) -> None:
    """Lay out a grid of panels under a title and one shared legend.

    ``tight_layout`` rather than constrained layout: the log-scale twin axes make each
    layout pass slow, and one pass is enough for a regular grid.
    """
    height = fig.get_figheight()
    fig.tight_layout(rect=(0, 0, 1, 1 - 0.7 / height), h_pad=1.8, w_pad=1.2)
    fig.suptitle(title, y=1 - 0.05 / height, va="top", fontweight="bold", fontsize=13)
    _shared_legend(fig, cases, y=1 - 0.33 / height)


def _shared_legend(fig, cases: Sequence[CaseResult], y: float) -> None:
    """One legend for the whole figure: features drawn, truth, output, trajectory error."""
    drawn = {f for c in cases for f in c.features}
    features = [f for f in ALL_FEATURES if f in drawn] + sorted(drawn - set(ALL_FEATURES))
    handles = [Line2D([], [], color=FEATURE_COLORS.get(f), marker="o", ms=4, label=f) for f in features]
    handles += [
        Line2D([], [], color="k", ls="--", lw=1, label="true weight"),
        Line2D([], [], color="gray", lw=6, alpha=0.25, label="output iteration"),
        Line2D([], [], color="goldenrod", lw=2, alpha=0.7, label="trajectory error (right, log)"),
    ]
    fig.legend(handles=handles, loc="upper center", bbox_to_anchor=(0.5, y), ncol=len(handles), frameon=False)


def _seeds(cases: Sequence[CaseResult]) -> str:
    return ", ".join(str(s) for s in sorted({c.seed for c in cases})) or "-"


def _shorten(text: str, limit: int = 80) -> str:
    return text if len(text) <= limit else text[: limit - 3] + "..."


# --------------------------------------------------------------------------- Figure 6


#: Marker of each named weight set's dots in Figure 6 (custom sets: a plus).
WEIGHT_SET_MARKERS = {"nominal": "o", "penalize-hip": "^", "penalize-knee": "s", "penalize-dtau": "D"}


def plot_figure6(results: Sequence[CaseResult], path: str | os.PathLike) -> Path:
    """Figure 6: weight error (top) and trajectory error (bottom, log) per condition.

    One bar per algorithm in each condition's group: the mean over weight sets and seeds
    of the cases that did not fail; every such case is a dot (marker: weight set; hollow
    if the algorithm stopped without converging). Failed cases are left out of the means
    and counted below the plot, so a bar never hides that its algorithm gave up.
    """
    if not results:
        raise ValueError("no results to plot")
    conditions = condition_order(r.condition for r in results)
    algorithms = sorted({r.algorithm for r in results})
    width = max(8.0, 1.1 * len(conditions) * (1 + 0.4 * len(algorithms)))
    fig, axes = plt.subplots(2, 1, figsize=(width, 8.4))
    labels = ("weight error: mean |w - w*|", "trajectory error (log scale)")
    for ax, metric, label in zip(axes, ("weight_error", "trajectory_error"), labels):
        for k, alg in enumerate(algorithms):
            for i, cond in enumerate(conditions):
                group = [r for r in results if (r.algorithm, r.condition) == (alg, cond)]
                x = i - 0.4 + 0.8 / len(algorithms) * (k + 0.5)
                _bar_group(ax, x, 0.8 / len(algorithms), group, metric, _algorithm_color(k))
        ax.set_title(label)
        ax.set_xticks(range(len(conditions)), conditions)
        ax.set_xlim(-0.6, len(conditions) - 0.4)
        ax.grid(axis="y", alpha=0.3)
    axes[0].set_ylim(bottom=0)
    axes[1].set_yscale("log")
    handles = _figure6_handles(algorithms, weight_set_order(r.weight_set for r in results))
    _finish_figure6(fig, handles, _excluded_note(results))
    return save_figure(fig, path)


def _finish_figure6(fig, handles: list, note: str) -> None:
    """Title on top; legend and the excluded-cases note in a band below the panels."""
    height = fig.get_figheight()
    ncol = min(len(handles), 7)
    band = (0.3 * -(-len(handles) // ncol) + 0.2) / height
    fig.tight_layout(rect=(0, band, 1, 1 - 0.35 / height), w_pad=2.0)
    fig.suptitle(
        "Figure 6: errors of the IOC estimate per condition (bar: mean; dots: cases)",
        y=1 - 0.05 / height,
        va="top",
        fontweight="bold",
        fontsize=13,
    )
    fig.legend(handles=handles, loc="upper center", bbox_to_anchor=(0.5, band), ncol=ncol, frameon=False)
    if note:
        fig.text(0.5, 0.0, note, ha="center", va="top", fontsize=9, color="firebrick")


def _bar_group(ax, x: float, width: float, cases: Sequence[CaseResult], metric: str, color: str) -> None:
    """One bar (mean of the scored cases) with its cases as dots, or a note if none scored."""
    scored = [r for r in cases if not r.failed and np.isfinite(getattr(r, metric))]
    if not scored:
        if cases:
            text = "all failed" if all(r.failed for r in cases) else "no score"
            ax.text(
                x,
                0.01,
                text,
                ha="center",
                va="bottom",
                rotation=90,
                fontsize=8,
                color=color,
                transform=ax.get_xaxis_transform(),
            )
        return
    order = weight_set_order(r.weight_set for r in scored)
    scored.sort(key=lambda r: (order.index(r.weight_set), r.seed))
    values = np.array([getattr(r, metric) for r in scored], dtype=float)
    mean = float(values.mean())
    ax.bar(x, mean, width * 0.9, color=color, alpha=0.35, edgecolor=color)
    shown = np.maximum(values, _LOG_FLOOR) if metric == "trajectory_error" else values
    offsets = np.linspace(-0.3, 0.3, len(values)) * width if len(values) > 1 else [0.0]
    for r, v, dx in zip(scored, shown, offsets):
        face = color if r.status == "converged" else "white"
        marker = WEIGHT_SET_MARKERS.get(r.weight_set, "P")
        ax.scatter(x + dx, v, s=28, marker=marker, facecolors=face, edgecolors=color, linewidths=1.2, zorder=3)
    ax.annotate(
        f"{mean:.2g}",
        (x, mean),
        xytext=(0, 2),
        textcoords="offset points",
        ha="center",
        va="bottom",
        fontsize=8,
        zorder=4,
        bbox={"boxstyle": "round,pad=0.1", "fc": "white", "ec": "none", "alpha": 0.7},
    )


def _algorithm_color(k: int) -> str:
    return f"C{k % 10}"


def _figure6_handles(algorithms: Sequence[str], weight_sets: Sequence[str]) -> list:
    """Legend: one patch per algorithm, one grey marker per weight set, the hollow-dot key."""
    handles: list = [Patch(color=_algorithm_color(k), alpha=0.5, label=a) for k, a in enumerate(algorithms)]
    handles += [
        Line2D([], [], ls="", marker=WEIGHT_SET_MARKERS.get(ws, "P"), color="0.35", label=ws) for ws in weight_sets
    ]
    handles.append(Line2D([], [], ls="", marker="o", mfc="white", color="0.35", label="hollow: stopped unconverged"))
    return handles


def _excluded_note(results: Sequence[CaseResult]) -> str:
    """Which cases the means leave out: failed ones, and unscored trajectory errors."""
    failed = _count((r.algorithm, r.condition) for r in results if r.failed)
    unscored = _count(
        (r.algorithm, r.condition) for r in results if not r.failed and not np.isfinite(r.trajectory_error)
    )
    parts = []
    if failed:
        parts.append(f"{sum(failed.values())} failed case(s) excluded from the means: {_fmt_counts(failed)}")
    if unscored:
        parts.append(f"{sum(unscored.values())} case(s) without a trajectory error: {_fmt_counts(unscored)}")
    return "\n".join(parts)


def _count(keys: Iterable[tuple[str, str]]) -> dict[tuple[str, str], int]:
    counts: dict[tuple[str, str], int] = {}
    for key in keys:
        counts[key] = counts.get(key, 0) + 1
    return counts


def _fmt_counts(counts: dict[tuple[str, str], int]) -> str:
    return "; ".join(f"{alg} / {cond}: {n}" for (alg, cond), n in sorted(counts.items()))


# --------------------------------------------------------------------------- everything


def output_names(results: Sequence[CaseResult]) -> dict[str, str]:
    """Figure name -> file name of everything :func:`make_figures` writes for ``results``.

    File names are built from checked identifiers only (an algorithm's name and config
    digest, :func:`~ioc_bench.synthetic.results.run_slug`) and each must be a plain file name
    (:func:`~ioc_bench.paths.check_file_name`): content never names a path. Raises
    ``ValueError`` otherwise.
    """
    slugged = _slugged(results)
    names = {"table1": "table1.md"}
    for alg in sorted({r.algorithm for r in slugged}):
        for figure, conditions in (("figure4", ("ideal",)), ("figure5", FIGURE5_CONDITIONS)):
            if any(r.algorithm == alg and r.condition in conditions for r in slugged):
                names[f"{figure}_{alg}"] = check_file_name(f"{figure}_{alg}.png")
    names["figure6"] = "figure6.png"
    if robustness_curves(slugged):
        names["robustness"] = "robustness.png"
    return names


def _slugged(results: Sequence[CaseResult]) -> list[CaseResult]:
    """Results whose ``algorithm`` is their run's slug (one config of one algorithm), checked."""
    return [replace(r, algorithm=check_file_name(run_slug(r), "algorithm name")) for r in results]


@dataclass(frozen=True)
class FigurePlan:
    """What :func:`make_figures` writes, every input and output checked (:func:`plan_figures`).

    Attributes:
        results: the selected results, each ``algorithm`` its run's checked slug.
        out: the output folder.
        names: figure name -> file name in ``out`` (:func:`output_names`).
    """

    results: tuple[CaseResult, ...]
    out: Path
    names: dict[str, str]

    def draw(self) -> dict[str, Path]:
        """Draw and write every figure; returns figure name -> path, in :attr:`names` order."""
        results, out, names = self.results, self.out, self.names
        written = {"table1": write_table1(results, out / names["table1"])}
        for figure, plot in (("figure4", plot_figure4), ("figure5", plot_figure5)):
            for alg in sorted({r.algorithm for r in results}):
                if f"{figure}_{alg}" in names:
                    written[f"{figure}_{alg}"] = plot(results, alg, out / names[f"{figure}_{alg}"])
        written["figure6"] = plot_figure6(results, out / names["figure6"])
        if "robustness" in names:
            written["robustness"] = plot_robustness(results, out / names["robustness"])
        return dict(sorted(written.items(), key=lambda kv: list(names).index(kv[0])))


def plan_figures(
    results_dir: str | os.PathLike,
    out_dir: str | os.PathLike,
    algorithms: Sequence[str] | None = None,
    *,
    out_name: str = "out_dir",
) -> FigurePlan:
    """Read and check everything :func:`make_figures` needs, before anything is drawn.

    Raises ``ValueError`` as :func:`~ioc_bench.runner.results.select_results` does, for a
    result whose algorithm cannot name a file (:func:`output_names`), and
    :class:`~ioc_bench.paths.PathError` (its message starting with ``out_name``) for an
    ``out_dir``, or a file in it, that cannot be written (:mod:`ioc_bench.paths`' checks).
    """
    selected = [r for r in select_results(results_dir, algorithms) if isinstance(r, CaseResult)]
    if not selected:  # a human case's figure is beside its result file
        raise ValueError(f"{results_dir} holds human-track cases only: their figures are beside their result files")
    names = output_names(selected)
    try:
        out = check_output_dir(out_dir)
        for name in names.values():
            check_output_file(out / name)
    except PathError as exc:
        raise PathError(f"{out_name}: {exc}") from None
    return FigurePlan(tuple(_slugged(selected)), out, names)


def make_figures(
    results_dir: str | os.PathLike, out_dir: str | os.PathLike, algorithms: Sequence[str] | None = None
) -> dict[str, Path]:
    """Write Table I and Figures 4-6 for the algorithms in ``results_dir`` into ``out_dir``.

    Returns figure name -> path: ``table1`` (always, saying so if it has no data),
    ``figure4_<algorithm>`` / ``figure5_<algorithm>`` for algorithms with ideal /
    imperfect-condition cases, ``figure6``, and ``robustness`` for robustness-suite results
    (see :func:`output_names`). Raises ``ValueError`` as :func:`plan_figures` does, before
    drawing anything.
    """
    return plan_figures(results_dir, out_dir, algorithms).draw()


def plot_robustness(results: Sequence[CaseResult], path: str | os.PathLike) -> Path:
    """Weight error against severity, one panel per axis, a line per algorithm with its interval;
    below, the coverage of the algorithms' 95 % weight regions at each severity."""
    found = robustness_curves(results)
    labels = sorted({c.label for c in found})
    fig, grid = plt.subplots(2, 3, figsize=(15, 8.4), sharey="row", height_ratios=(1.4, 1))
    axes, cover_axes = grid
    for ax, axis in zip(cover_axes, AXES):
        for k, label in enumerate(labels):
            curve = next((c for c in found if c.label == label and c.axis == axis), None)
            if curve is not None and np.any(np.isfinite(curve.coverage)):
                ax.plot(curve.severity, curve.coverage, "s-", color=_algorithm_color(k), label=label)
        ax.axhline(0.95, color="k", linestyle="--", linewidth=0.8, label="nominal 0.95")
        ax.set_ylim(-0.05, 1.05)
        ax.set_title(f"{axis}: share of 95 % weight regions holding the truth")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7)
    cover_axes[0].set_ylabel("coverage (algorithms without regions not shown)")
    for ax, axis in zip(axes, AXES):
        for k, label in enumerate(labels):
            curve = next((c for c in found if c.label == label and c.axis == axis), None)
            if curve is None:
                continue
            color = _algorithm_color(k)
            ax.plot(curve.severity, curve.mean, "o-", color=color, label=f"{label} (AUC {curve.auc:.3g})")
            ax.fill_between(curve.severity, curve.low, curve.high, color=color, alpha=0.15)
        unit = "noise sigma, % of each signal's span" if axis == "noise" else f"{axis} error of the IOC's model, %"
        ax.set_xlabel(unit)
        cover_axes[list(AXES).index(axis)].set_xlabel(unit)
        ax.set_title(f"{axis}: weight error against severity")
        ax.set_yscale("symlog", linthresh=1e-3)
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7)
    axes[0].set_ylabel("mean weight error (95 % bootstrap over cases)")
    fig.suptitle("Robustness curves (robustness suite; severity 0 is the ideal condition)", fontweight="bold")
    fig.tight_layout()
    return save_figure(fig, path)


__all__ = [
    "FIGURE5_CONDITIONS",
    "TABLE1_CONDITIONS",
    "FigurePlan",
    "make_figures",
    "output_names",
    "plan_figures",
    "plot_figure4",
    "plot_figure5",
    "plot_figure6",
    "plot_robustness",
    "select_results",
    "table1_markdown",
    "write_table1",
]
