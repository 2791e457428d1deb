"""Figures of human steps beside the walker's: the four leg segments' angles over a step."""

from __future__ import annotations

import os
from collections.abc import Mapping, Sequence
from pathlib import Path

import numpy as np

from ioc_bench.human.record import HumanResult, SpeedScore
from ioc_bench.human.step import LEG_SEGMENTS
from ioc_bench.model.catalogue import DEFAULT_MODEL
from ioc_bench.plotting import plt, save_figure

_STYLES = ("--", ":", "-.")


def plot_human_fits(panels: Sequence[Mapping], path: str | os.PathLike, heading: str = "") -> Path:
    """One row per panel, one column per leg segment: the person's angles (solid black) and
    each walker step's (dashed), in degrees over the step (0 % and 100 % at heel strikes).

    Each panel is a mapping with ``title``, ``human`` ((T, 4) rad, :data:`LEG_SEGMENTS` order)
    and ``walkers`` (label -> (T, 4) rad). Optional keys let a row show other curves of the
    same shape (e.g. changes of angles between speeds): ``ylabel`` (default ``angle (deg)``),
    ``human_label`` (default ``person``) and ``zero_label`` (names the zero line in the
    legend). ``heading`` opens the figure's title.
    """
    if not panels:
        raise ValueError("no panels to plot")
    fig, axes = plt.subplots(len(panels), 4, figsize=(13, 2.4 * len(panels)), sharex=True, squeeze=False)
    for i, (row, panel) in enumerate(zip(axes, panels)):
        human = np.degrees(np.asarray(panel["human"]))
        s = np.linspace(0, 100, human.shape[0])
        for j, ax in enumerate(row):
            ax.plot(s, human[:, j], "k-", lw=2, label=panel.get("human_label", "person"))
            for style, (label, angles) in zip(_STYLES, panel["walkers"].items()):
                ax.plot(s, np.degrees(np.asarray(angles))[:, j], style, lw=1.5, label=label)
            zero = panel.get("zero_label")
            ax.axhline(0, color="0.6" if zero else "0.8", lw=1 if zero else 0.5, label=zero)
            if i == 0:  # (``row is axes[0]`` is never true: indexing makes a new array)
                ax.set_title(LEG_SEGMENTS[j].replace("_", " "))
            if j == 0:
                ax.set_ylabel(f"{panel['title']}\n{panel.get('ylabel', 'angle (deg)')}", fontsize=8)
        row[-1].legend(fontsize=7, loc="best")
    for ax in axes[-1]:
        ax.set_xlabel("% of the step")
    fig.suptitle(heading + "Leg segment angles from vertical (walker convention: + = proximal end ahead)", fontsize=10)
    return save_figure(fig, path)


def plot_human_case(record: HumanResult, humans: Mapping[str, np.ndarray], path: str | os.PathLike) -> Path:
    """The figure of one human-track case: the rows of :func:`case_panels`, titled with the
    case's model when it is not the walker."""
    model = "" if record.model == DEFAULT_MODEL else f"Model {record.model}. "
    return plot_human_fits(case_panels(record, humans), path, model)


def case_panels(record: HumanResult, humans: Mapping[str, np.ndarray]) -> list[dict]:
    """The rows of a case's figure: per scored speed (fits first), the person's leg segment
    angles, the estimated weights' step and the nominal weights' step; then, per prediction
    carried by continuation from another speed, the person's change of angles between the
    two speeds against the walker's (how well the walker adapts, which the angles alone hide).

    ``humans`` holds the person's (T, 4) angles (rad) by speed code. A failed case has no
    walker steps: its figure shows the person's steps alone. A change whose source speed is
    not in ``humans`` is left out.
    """
    angles = [_angle_panel(record, code, human) for code, human in humans.items()]
    changes = [_change_panel(record, record.scores[code], humans) for code in humans if code in record.scores]
    return angles + [panel for panel in changes if panel is not None]


def _angle_panel(record: HumanResult, code: str, human: np.ndarray) -> dict:
    """The row of one speed: the person's angles, the estimate's and the nominal's steps."""
    score = record.scores.get(code)
    walkers = {}
    if score is not None:
        for label, rmse in (("estimate", score.rmse_deg), ("nominal", score.nominal_rmse_deg)):
            if score.angles.get(label) is not None:
                walkers[f"{label} ({_deg(rmse)})"] = np.asarray(score.angles[label])
    role = score.role if score is not None else record.status
    copy = f", copy {_deg(score.copy_rmse_deg)}" if score is not None and score.copy_from else ""
    skill = f"skill {_num(score.skill)}{copy}" if score is not None else ""
    return {"title": f"{record.subject} {code} {role}\n{skill}", "human": human, "walkers": walkers}


def _change_panel(record: HumanResult, score: SpeedScore, humans: Mapping[str, np.ndarray]) -> dict | None:
    """The row of the change from ``score.continued_from`` to ``score``'s speed: the person's
    (solid), the walker's (dashed; absent if either step failed) and zero, the copy's
    prediction. None when the speed was not continued, or the person's source step is missing."""
    source = score.continued_from
    if not source or source not in humans or score.speed_code not in humans:
        return None
    human = np.asarray(humans[score.speed_code]) - np.asarray(humans[source])
    walkers = {}
    here = score.angles.get("estimate")
    there = record.scores[source].angles.get("estimate") if source in record.scores else None
    if here is not None and there is not None:
        walkers[f"walker's change (R^2 {_num(score.change_r2)})"] = np.asarray(here) - np.asarray(there)
    left = ", left its family" if score.family_changed else ""
    lengths = f"step {_num(score.step_length_walker)} L (person {_num(score.step_length)}){left}"
    return {
        "title": f"{source}->{score.speed_code} change\n{lengths}",
        "human": human,
        "walkers": walkers,
        "ylabel": "change (deg)",
        "human_label": "person's change",
        "zero_label": "copy predicts no change",
    }


def _deg(value) -> str:
    return "failed" if value is None or not np.isfinite(value) else f"{value:.1f} deg"


def _num(value) -> str:
    return "n/a" if value is None or not np.isfinite(value) else f"{value:.2f}"
