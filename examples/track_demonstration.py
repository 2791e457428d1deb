"""A demonstration as a Gymnasium policy: four walkers with different leg masses track one optimal step.

Makes a demonstration (one start: a few seconds), walks it for 10 steps in a vector
environment of 4 whose legs weigh 0.9, 1.0, 1.1 and 1.2 times the nominal, records a
GIF of the four (stick figures, headless) and prints each walker's tracking error.

    python examples/track_demonstration.py [--out track_demonstration.gif]
"""

from __future__ import annotations

import argparse
from pathlib import Path

import gymnasium as gym
import numpy as np

import envs
import ioc_bench
from envs.drawing import write_gif

LEG_MASS_SCALES = (0.9, 1.0, 1.1, 1.2)


def main(demo: ioc_bench.Demonstration | None = None, out: str = "track_demonstration.gif", steps: int = 10) -> dict:
    demo = demo or ioc_bench.optimize_gait("nominal", task=ioc_bench.Task(speed=0.27), starts=1, seed=0)
    policy = envs.TrackingPolicy(demo)

    # Time for the steps at up to twice the demonstration's step duration (the registered
    # 1000 env steps, 10 time units, are fewer than 10 of the benchmark's steps).
    limit = int(2 * steps * demo.trajectory.duration / 0.01)

    def make(scale: float):  # every episode, autoreset included, starts from the demonstration
        params = demo.params.with_leg_mass_scale(scale)
        kwargs = {"render_mode": "rgb_array", "renderer": "stick", "width": 240, "height": 180}
        return lambda: gym.make(
            envs.PLANAR_WALKER_ID, params=params, demonstration=demo, max_episode_steps=limit, **kwargs
        )

    vec = gym.vector.SyncVectorEnv([make(s) for s in LEG_MASS_SCALES])
    obs, info = vec.reset(seed=0)
    errors, fell, slow, frames, t = [[] for _ in LEG_MASS_SCALES], np.zeros(4, bool), np.zeros(4, bool), [], 0
    while not np.all(fell | slow | (info["heel_strikes"] >= steps)):
        commands = [policy.command(o, {"stance_leg": leg}) for o, leg in zip(obs, info["stance_leg"])]
        walking = ~(fell | slow | (info["heel_strikes"] >= steps))
        for i, cmd in enumerate(commands):
            if walking[i]:
                errors[i].append(cmd.joints_ref - cmd.joints)
        if t % 5 == 0:  # 20 frames per time unit: a 2x2 mosaic of the four walkers
            top, bottom = np.split(np.array(vec.render()), 2)
            frames.append(np.concatenate([np.concatenate(top, axis=1), np.concatenate(bottom, axis=1)]))
        obs, _, terminated, truncated, info = vec.step(np.array([c.action for c in commands], dtype=np.float32))
        fell |= terminated & walking
        slow |= truncated & walking
        t += 1
    vec.close()
    gif = write_gif(Path(out), frames, fps=20)
    rms = [float(np.sqrt(np.mean(np.square(e)))) for e in errors]
    for scale, err, down, late in zip(LEG_MASS_SCALES, rms, fell, slow):
        outcome = "fell" if down else "out of time" if late else f"{steps} steps"
        print(f"legs x{scale:.1f}: {outcome}, tracking error RMS {err:.2e} rad")
    print(f"wrote {gif} ({len(frames)} frames, {t} environment steps of {t * 0.01:.2f} time units)")
    return {"rms": rms, "fell": fell.tolist(), "out_of_time": slow.tolist(), "gif": gif}


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", default="track_demonstration.gif", help="GIF to write")
    main(out=parser.parse_args().out)
