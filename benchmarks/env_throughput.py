"""Environment steps per second: IOCBench/PlanarWalker (v2) beside Gymnasium's Walker2d-v5, in one run.

Both environments are made with ``gymnasium.make`` (so with Gymnasium's standard
wrappers, as users run them) and stepped with seeded random actions from their action
spaces, resetting whenever an episode ends; resets count in the time. Rounds alternate
between the environments, so both see the same machine load, and the medians over the
rounds are printed, with the median of the per-round ratios. Walker2d-v5 needs
Gymnasium's MuJoCo extra (``pip install 'gymnasium[mujoco]'``, for ``imageio``).

Usage::

    python benchmarks/env_throughput.py                       # defaults: 7 rounds of 2000 steps
    python benchmarks/env_throughput.py --timestep 0.0005 --frame-skip 20   # another physics step
"""

from __future__ import annotations

import argparse
import statistics
import sys
import time

import gymnasium as gym
import mujoco
import numpy as np

import envs
from ioc_bench.model.mjcf import ContactSettings

WALKER2D_ID = "Walker2d-v5"


def steps_per_second(env: gym.Env, steps: int, seed: int) -> float:
    """Steps per second of ``steps`` random-action steps (seeded), resets included."""
    env.action_space.seed(seed)
    actions = [env.action_space.sample() for _ in range(steps)]
    env.reset(seed=seed)
    start = time.perf_counter()
    for action in actions:
        _, _, terminated, truncated, _ = env.step(action)
        if terminated or truncated:
            env.reset()
    return steps / (time.perf_counter() - start)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--steps", type=int, default=2000, help="steps per round (default 2000)")
    parser.add_argument("--rounds", type=int, default=7, help="rounds per environment (default 7)")
    parser.add_argument("--seed", type=int, default=0, help="seed of the actions and resets (default 0)")
    parser.add_argument("--timestep", type=float, default=None, help="walker physics timestep (default: its own)")
    parser.add_argument("--frame-skip", type=int, default=None, help="physics steps per walker step (default: its own)")
    args = parser.parse_args(argv)
    kwargs = {}
    if args.timestep is not None:
        kwargs["contact"] = ContactSettings(timestep=args.timestep)
    if args.frame_skip is not None:
        kwargs["frame_skip"] = args.frame_skip
    try:
        walker2d = gym.make(WALKER2D_ID)
    except Exception as exc:  # Gymnasium's MuJoCo extra missing
        print(f"cannot make {WALKER2D_ID}: {exc} (pip install 'gymnasium[mujoco]')", file=sys.stderr)
        return 2
    ours = gym.make(envs.PLANAR_WALKER_ID, **kwargs)
    rates: dict[str, list[float]] = {envs.PLANAR_WALKER_ID: [], WALKER2D_ID: []}
    for r in range(args.rounds):
        for env_id, env in ((envs.PLANAR_WALKER_ID, ours), (WALKER2D_ID, walker2d)):
            rates[env_id].append(steps_per_second(env, args.steps, args.seed + r))
    ratios = [a / b for a, b in zip(rates[envs.PLANAR_WALKER_ID], rates[WALKER2D_ID])]
    for env_id, env in ((envs.PLANAR_WALKER_ID, ours), (WALKER2D_ID, walker2d)):
        model = env.unwrapped.model
        integrator = mujoco.mjtIntegrator(model.opt.integrator).name.removeprefix("mjINT_")
        physics = f"{env.unwrapped.frame_skip} x {model.opt.timestep:g} {integrator}"
        values = rates[env_id]
        print(
            f"{env_id:<26} dt {env.unwrapped.dt:<6g} physics {physics:<28} "
            f"steps/s median {statistics.median(values):6.0f}  [min {min(values):.0f}, max {max(values):.0f}]"
        )
    print(
        f"ratio {envs.PLANAR_WALKER_ID} / {WALKER2D_ID}: median {statistics.median(ratios):.2f} "
        f"[min {min(ratios):.2f}, max {max(ratios):.2f}] over {args.rounds} rounds of {args.steps} steps "
        f"(load average {np.round(_load(), 2).tolist()})"
    )
    ours.close()
    walker2d.close()
    return 0


def _load() -> tuple[float, ...]:
    try:
        import os

        return os.getloadavg()
    except OSError:
        return ()


if __name__ == "__main__":
    sys.exit(main())
