"""The paper's Figure 4 for one case: candidate weights per iteration against the truth."""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np

from ioc_bench.plotting import plt, save_figure
from ioc_bench.viz.common import FEATURE_COLORS


def draw_convergence(ax, result, legend: bool = True) -> None:
    """Draw one case's convergence on ``ax`` (weights left axis, trajectory error right).

    ``result`` is a :class:`~ioc_bench.synthetic.case.CaseResult` (or anything with its fields).
    """
    its = np.arange(len(result.history))
    weights = _weights(result.history, len(result.features))
    for j, feature in enumerate(result.features):
        color = FEATURE_COLORS.get(feature, None)
        if len(its):
            ax.plot(its, weights[:, j], "-o", ms=3, color=color, label=feature)
        ax.axhline(result.true_weights[j], ls="--", lw=1, color=color)
    if result.chosen_iteration is not None and len(its):
        ax.axvline(result.chosen_iteration, color="gray", lw=6, alpha=0.25, label="output")
    ax.set_ylim(-0.05, 1.05)
    ax.set_xlabel("iteration")
    ax.set_ylabel("weight (unit norm)")
    err = np.array([_number(h.get("trajectory_error")) for h in result.history], dtype=float)
    if np.any(np.isfinite(err) & (err > 0)):
        ax2 = ax.twinx()
        ax2.semilogy(its, err, color="goldenrod", alpha=0.7, lw=2)
        ax2.set_ylabel("trajectory error of the iteration's step", color="goldenrod")
    if legend and ax.get_legend_handles_labels()[0]:
        ax.legend(fontsize=7, loc="upper right")


def _weights(history, n: int) -> np.ndarray:
    """(iterations, n) weights per iteration; NaN where a record has no such weights.

    A failed case has no iterations (an empty (0, n) array, drawn as an empty plot).
    """
    rows = []
    for h in history:
        w = h.get("weights")
        ok = isinstance(w, (list, tuple)) and len(w) == n
        rows.append([_number(x) for x in w] if ok else [np.nan] * n)
    return np.array(rows, dtype=float).reshape(len(rows), n)


def _number(x) -> float:
    return float(x) if isinstance(x, (int, float)) and not isinstance(x, bool) else np.nan


def plot_convergence(result, path: str | os.PathLike) -> Path:
    """Write the convergence plot of one case to ``path``."""
    fig, ax = plt.subplots(figsize=(7, 4))
    draw_convergence(ax, result)
    ax.set_title(
        f"{result.algorithm}: {result.weight_set} weights, {result.condition} condition, seed {result.seed}\n"
        f"weight error {result.weight_error:.4f}, {result.n_solves} forward solves, {result.wall_time:.1f} s "
        "(dashed: true weights)",
        fontsize=9,
    )
    return save_figure(fig, path)
