"""How fine must the environment's physics step be? The replay checks and the contact, per integrator and timestep.

For each configuration (integrator and physics timestep) and each demonstration this runs:

- the inverse-dynamics check (no time integration: the same at every timestep, shown as a control);
- the open-loop replay, its final error against the demonstration and against the same
  replay at a 16x finer RK4 step of 3.125e-5 (integration error alone);
- the closed-loop check through ``env.step`` (control every 0.0025, as ``ioc-bench replay``)
  and the same walk at the environment's own control period 0.01: steps walked,
  feedback share, tracking RMS;
- the contact in the closed-loop check: the fraction of environment steps that ended with
  the stance foot on the floor, and the deepest stance-foot penetration (leg lengths);
- random play: 20000 environment steps (dt 0.01) of seeded random actions from the
  standing start, resetting on falls: episodes, median episode length, the share of steps
  with a velocity above 10, the largest velocity and penetration, MuJoCo's warnings
  (instabilities) summed over episodes.

Usage::

    python benchmarks/physics_step.py                 # the eight demonstrations, single-start
    python benchmarks/physics_step.py a.npz b.npz     # given demonstrations
    python benchmarks/physics_step.py --configs rk4:0.0005,rk4:0.002

Without files it makes the benchmark's eight demonstrations (four weight sets at speeds
0.27 and 0.34) from one start each (seed 0, about 15 s); the benchmark's own come from
15 starts. Only RK4 is the generated model's integrator: other integrators are set on the
compiled model here, for the measurement only.
"""

from __future__ import annotations

import argparse
import contextlib
import sys
import tempfile
from collections.abc import Iterator
from pathlib import Path

import mujoco
import numpy as np

import envs.planar_walker as planar_walker
from envs.checks import closed_loop_replay, inverse_dynamics_check, open_loop_replay
from envs.drawing import stick_points
from envs.planar_walker import PlanarWalkerEnv
from ioc_bench import Demonstration, Task, optimize_gait
from ioc_bench.model.mjcf import ContactSettings
from ioc_bench.weights import WEIGHT_SETS

INTEGRATORS = {
    "rk4": mujoco.mjtIntegrator.mjINT_RK4,
    "euler": mujoco.mjtIntegrator.mjINT_EULER,
    "implicitfast": mujoco.mjtIntegrator.mjINT_IMPLICITFAST,
}
DEFAULT_CONFIGS = "rk4:0.0005,rk4:0.001,rk4:0.00125,rk4:0.002,euler:0.0005,euler:0.001"
#: The open-loop reference step (RK4), 16x finer than the finest configuration above.
FINE_TIMESTEP = 0.0005 / 16
SPEEDS = (0.27, 0.34)


@contextlib.contextmanager
def integrator(name: str) -> Iterator[None]:
    """Make every environment built inside use integrator ``name`` (measurement only)."""
    build = planar_walker.build_model

    def patched(params=None, contact=None):
        model = build(params, contact)
        model.opt.integrator = INTEGRATORS[name]
        return model

    planar_walker.build_model = patched
    try:
        yield
    finally:
        planar_walker.build_model = build


def eight_demonstrations(folder: Path) -> list[Path]:
    """The four weight sets at both speeds, one start each, saved in ``folder``."""
    paths = []
    for name in WEIGHT_SETS:
        for speed in SPEEDS:
            demo = optimize_gait(name, task=Task(speed), starts=1, seed=0, workers=1)
            paths.append(demo.save(folder / f"{name}_{speed}.npz"))
    return paths


def stance_penetration(demo: Demonstration, qpos: np.ndarray, stance: np.ndarray) -> float:
    """Deepest stance-foot point below the floor's surface over recorded frames (leg lengths)."""
    depths = [-stick_points(demo.params, q)[leg][-1, 1] for q, leg in zip(qpos, stance)]
    return max(0.0, float(np.max(depths)))


def measure(demo: Demonstration, name: str, timestep: float, fine_final: np.ndarray) -> dict[str, float]:
    contact = ContactSettings(timestep=timestep)
    with integrator(name):
        ol = open_loop_replay(demo, contact=contact)
        check = closed_loop_replay(demo, contact=contact)
        user = closed_loop_replay(demo, contact=contact, control_dt=0.01)
    return {
        "id": inverse_dynamics_check(demo).relative_residual,
        "ol_demo": ol.final_position_error,
        "ol_fine": float(np.abs(ol.qpos[-1] - fine_final).max()),
        "steps": check.steps_walked,
        "share": check.feedback_share,
        "rms": check.tracking_rms,
        "contact": check.stance_contact,
        "depth": stance_penetration(demo, check.qpos, check.stance),
        "steps_01": user.steps_walked,
        "share_01": user.feedback_share,
    }


def random_play(name: str, timestep: float, steps: int = 20000, seed: int = 0) -> dict[str, float]:
    """Seeded random actions from the standing start (dt 0.01), resetting on falls."""
    with integrator(name):
        env = PlanarWalkerEnv(contact=ContactSettings(timestep=timestep), frame_skip=round(0.01 / timestep))
    env.action_space.seed(seed)
    env.reset(seed=seed)
    lengths, length, speeds, depth, warnings = [], 0, [], 0.0, 0
    for _ in range(steps):
        obs, _, terminated, _, _ = env.step(env.action_space.sample())
        length += 1
        speeds.append(float(np.abs(obs[6:13]).max()) if np.all(np.isfinite(obs)) else np.inf)
        if env.data.ncon:
            depth = max(depth, -float(env.data.contact.dist[: env.data.ncon].min()))
        if terminated:
            warnings += sum(w.number for w in env.data.warning)
            lengths.append(length)
            length = 0
            env.reset()
    warnings += sum(w.number for w in env.data.warning)
    v = np.array(speeds)
    return {
        "episodes": len(lengths),
        "length": float(np.median(lengths)),
        "fast": float(np.mean(v > 10)),
        "vmax": float(v.max()),
        "depth": depth,
        "warnings": warnings,
    }


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("demos", nargs="*", type=Path, help="demonstration files (default: make the eight)")
    parser.add_argument("--configs", default=DEFAULT_CONFIGS, help="integrator:timestep, comma-separated")
    args = parser.parse_args(argv)
    configs = [(c.split(":")[0], float(c.split(":")[1])) for c in args.configs.split(",")]
    for name, _ in configs:
        if name not in INTEGRATORS:
            parser.error(f"unknown integrator {name!r}; valid: {', '.join(INTEGRATORS)}")
    with tempfile.TemporaryDirectory() as tmp:
        paths = args.demos or eight_demonstrations(Path(tmp))
        demos = {p.stem: Demonstration.load(p) for p in paths}
    fine = {k: open_loop_replay(d, contact=ContactSettings(timestep=FINE_TIMESTEP)).qpos[-1] for k, d in demos.items()}
    print(f"{len(demos)} demonstrations: {', '.join(demos)}")
    print(
        "config            | ID resid max | open loop vs demo (median) | vs fine step (median, max) | "
        "check: min steps, share median [min, max], RMS median | stance contact min | depth max | "
        "dt 0.01: min steps, share median"
    )
    for name, timestep in configs:
        rows = [measure(d, name, timestep, fine[k]) for k, d in demos.items()]
        col = {key: np.array([r[key] for r in rows]) for key in rows[0]}
        print(
            f"{name:>12} {timestep:<7g} | {col['id'].max():.1e}      | {np.median(col['ol_demo']):.2e}"
            f"                   | {np.median(col['ol_fine']):.1e}, {col['ol_fine'].max():.1e}           | "
            f"{col['steps'].min():2d}, {np.median(col['share']):.3f} [{col['share'].min():.3f}, "
            f"{col['share'].max():.3f}], {np.median(col['rms']):.1e}        | {col['contact'].min():.3f}"
            f"              | {col['depth'].max():.1e}   | "
            f"{col['steps_01'].min():2d}, {np.median(col['share_01']):.3f}",
            flush=True,
        )
        per_demo = " ".join(f"{k}={r['share']:.3f}" for k, r in zip(demos, rows))
        print(f"{'':>20}check share per demo: {per_demo}", flush=True)
    print("random play         | episodes | median length | share |v| > 10 | max |v| | max penetration | warnings")
    for name, timestep in configs:
        r = random_play(name, timestep)
        print(
            f"{name:>12} {timestep:<7g} | {r['episodes']:8d} | {r['length']:13.0f} | {r['fast']:14.3f} | "
            f"{r['vmax']:7.1f} | {r['depth']:15.4f} | {r['warnings']}",
            flush=True,
        )
    return 0


if __name__ == "__main__":
    sys.exit(main())
