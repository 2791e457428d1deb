"""What the replay writes: a comparison figure of the three checks and a GIF of the closed-loop walk."""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np

from envs.checks.closed_loop import ClosedLoopResult
from envs.checks.open_loop import OpenLoopResult
from envs.coordinates import actuated_dofs
from envs.reference import DemoReference
from ioc_bench.demo import Demonstration
from ioc_bench.model.params import WalkerParams
from ioc_bench.model.walker import ACTUATORS


def write_animation(
    closed: ClosedLoopResult,
    params: WalkerParams,
    path: str | os.PathLike,
    fps: float = 20.0,
    speed: float = 1.0,
) -> Path:
    """GIF of the closed-loop walk (stick figure), ``speed`` time units per second of GIF."""
    from envs.drawing import StickRenderer, write_gif

    renderer = StickRenderer(params, 320, 240)
    step = max(1, round(speed / fps / float(np.median(np.diff(closed.times)))))
    strikes = np.asarray(closed.heel_strikes)
    frames = [
        renderer.render(qpos, f"t = {t:5.2f}   step {int(np.sum(strikes <= t)) + 1}")
        for t, qpos in zip(closed.times[::step], closed.qpos[::step])
    ]
    renderer.close()
    return write_gif(path, frames, fps)


def plot_comparison(
    demo: Demonstration,
    open_loop: OpenLoopResult,
    closed: ClosedLoopResult,
    path: str | os.PathLike,
) -> Path:
    """Joint angles and torques: demonstration vs MuJoCo open loop vs every closed-loop step."""
    from ioc_bench.plotting import plt, save_figure

    ref = DemoReference.of(demo)
    fig, axes = plt.subplots(3, 2, figsize=(10, 9))
    dofs = actuated_dofs("a")
    demo_q = np.column_stack([ref.qpos[:, 2], ref.qpos[:, dofs]])
    open_q = np.column_stack([open_loop.qpos[:, 2], open_loop.qpos[:, dofs]])
    closed_q = np.column_stack([closed.qpos[:, 2], closed.joints])
    starts = np.flatnonzero(np.r_[True, closed.stance[1:] != closed.stance[:-1]])
    for j, (ax, name) in enumerate(zip(axes.ravel()[:5], ("torso", *ACTUATORS))):
        for s, e in zip(starts, [*starts[1:], len(closed.times)]):
            ax.plot(closed.phase[s:e], closed_q[s:e, j], color="tab:blue", lw=0.8, alpha=0.6)
        ax.plot(ref.times, open_q[:, j], "--", color="tab:orange", lw=1.2)
        ax.plot(ref.times, demo_q[:, j], color="black", lw=2)
        ax.set_ylabel(f"{name.replace('_', ' ')} angle (rad)")
    axes[0, 0].plot([], [], color="black", lw=2, label="demonstration")
    axes[0, 0].plot([], [], "--", color="tab:orange", label="MuJoCo open loop")
    axes[0, 0].plot([], [], color="tab:blue", lw=0.8, label="MuJoCo closed loop, each step")
    axes[0, 0].legend(fontsize=7)
    ax = axes[2, 1]
    ax.plot(closed.times, np.abs(closed.tau_ff).sum(axis=1), color="black", lw=1, label="|feed-forward|")
    ax.plot(closed.times, np.abs(closed.tau_fb).sum(axis=1), color="tab:red", lw=1, label="|feedback|")
    ax.set_ylabel("|torque| summed over joints (m g L)")
    ax.set_xlabel("closed-loop time (sqrt(L/g))")
    ax.legend(fontsize=7)
    axes[2, 0].set_xlabel("step phase (demonstration time, sqrt(L/g))")
    fig.suptitle(
        f"MuJoCo replay: open-loop final error {open_loop.final_position_error:.3g}; "
        f"closed loop {closed.steps_walked}/{closed.steps_requested} steps, "
        f"feedback share {100 * closed.feedback_share:.1f} %",
        fontsize=10,
    )
    return save_figure(fig, path)


__all__ = ["plot_comparison", "write_animation"]
