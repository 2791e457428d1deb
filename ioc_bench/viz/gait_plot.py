"""The paper's left-column figure: the walker drawn through the step, its joint angles and torques."""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np

from ioc_bench.demo import Demonstration
from ioc_bench.model.catalogue import get_model
from ioc_bench.model.linkage import joint_angle, point_position
from ioc_bench.plotting import plt, save_figure


def _ends(segment) -> tuple[str, str]:
    """The two named points a segment is drawn between (its extreme points along its axis)."""
    by_along = sorted(segment.points, key=lambda p: segment.points[p][0])
    return by_along[0], by_along[-1]


SNAPSHOT_SPACING = 0.45
_LEG_COLORS = {"torso": "black", "stance": "tab:red", "swing": "tab:blue"}


def _color(segment: str) -> str:
    return next(c for key, c in _LEG_COLORS.items() if key in segment)


def plot_gait(demo: Demonstration, path: str | os.PathLike, snapshots: int = 7) -> Path:
    """Write a stick-figure + joint-angle + torque plot of ``demo`` to ``path``."""
    model = get_model(demo.model)
    link = model.linkage(demo.params)
    traj = demo.trajectory
    t = traj.times
    fig, (ax_fig, ax_q, ax_tau) = plt.subplots(3, 1, figsize=(7, 9), gridspec_kw={"height_ratios": [1.3, 1, 1]})
    # Snapshots are spread sideways (like the paper's figure) so they do not overlap.
    knots = np.linspace(0, traj.n_knots - 1, snapshots).round().astype(int)
    foot = traj.point(link, *model.roles.swing_foot)
    for j, k in enumerate(knots):
        dx = j * SNAPSHOT_SPACING
        for i, seg in enumerate(link.segments):
            a, b = (point_position(seg, p, traj.q[k][i]) for p in _ends(seg))
            ax_fig.plot([a[0] + dx, b[0] + dx], [a[1], b[1]], color=_color(seg.name), lw=2)
        ax_fig.plot(foot[: k + 1, 0] + dx, foot[: k + 1, 1], ":", color="tab:blue", lw=1)
        ax_fig.text(dx, -0.12, f"t={t[k]:.2f}", ha="center", fontsize=7)
    ax_fig.axhline(0, color="gray", lw=0.8)
    ax_fig.set_aspect("equal")
    ax_fig.set_ylim(-0.2, 1.7)
    ax_fig.axis("off")
    ax_fig.set_title(_title(demo) + "\nstance leg red, swing leg blue, dotted: swing-foot path", fontsize=9)
    for joint in link.joints:
        angle = [joint_angle(link, joint, qk[:, 2]) for qk in traj.q]
        ax_q.plot(t, angle, label=joint.name.replace("_", " "))
    ax_q.plot(t, traj.q[:, link.index(model.roles.torso), 2], "k--", label="torso")
    ax_q.set_ylabel("angle (rad)")
    ax_q.legend(fontsize=8, ncol=3)
    for i, joint in enumerate(link.actuated):
        ax_tau.plot(t, traj.tau[:, i], label=joint.name.replace("_", " "))
    ax_tau.set_ylabel("actuated torque (m g L)")
    ax_lock = ax_tau.twinx()
    for i, joint in enumerate(link.locked):
        ax_lock.plot(t, traj.lock[:, i], ":", color="gray", lw=1 + i, label=f"{joint.name.replace('_', ' ')} lock")
    ax_lock.set_ylabel("knee-lock torque (dotted)", color="gray")
    ax_lock.legend(fontsize=7, loc="lower right")
    ax_tau.set_xlabel("time (sqrt(L/g))")
    ax_tau.legend(fontsize=8, ncol=3)
    return save_figure(fig, path)


def _title(demo: Demonstration) -> str:
    w = ", ".join(f"{k} {v:.2f}" for k, v in demo.weights.items() if v)
    step = demo.trajectory.duration * demo.task.speed
    return f"weights {w}; speed {demo.task.speed:g}, step {step:.3f}"
