"""Milliseconds per rendered frame: the stick figure, MuJoCo's renderer, and what ``renderer="auto"`` picks.

MuJoCo's OpenGL backend is chosen by ``MUJOCO_GL`` before MuJoCo is imported, so run
this once per backend::

    MUJOCO_GL=egl python benchmarks/render_cost.py
    python benchmarks/render_cost.py --frames 50 --width 480 --height 360

Prints the median over ``--frames`` frames of a walker stepping with zero torques.
"""

from __future__ import annotations

import argparse
import os
import statistics
import sys
import time

import numpy as np

from envs.planar_walker import PlanarWalkerEnv
from envs.rendering import RendererUnavailableError


def ms_per_frame(renderer: str, frames: int, width: int, height: int) -> tuple[float, str | None]:
    """Median milliseconds per ``render()`` (the first frame, which builds the renderer, excluded)."""
    env = PlanarWalkerEnv(render_mode="rgb_array", renderer=renderer, width=width, height=height)
    env.reset(seed=0)
    env.render()
    times = []
    for _ in range(frames):
        env.step(np.zeros(4, dtype=np.float32))
        start = time.perf_counter()
        env.render()
        times.append(time.perf_counter() - start)
    used = env.renderer_in_use
    env.close()
    return 1000 * statistics.median(times), used


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--frames", type=int, default=30, help="frames per renderer (default 30)")
    parser.add_argument("--width", type=int, default=480)
    parser.add_argument("--height", type=int, default=360)
    args = parser.parse_args(argv)
    print(f"MUJOCO_GL={os.environ.get('MUJOCO_GL', '(unset)')}, {args.width}x{args.height}")
    for renderer in ("stick", "mujoco", "auto"):
        try:
            ms, used = ms_per_frame(renderer, args.frames, args.width, args.height)
        except RendererUnavailableError as exc:
            print(f"renderer={renderer!r:9} unavailable: {exc}")
            continue
        print(f"renderer={renderer!r:9} draws with {used!r:9} {ms:7.1f} ms per frame (median of {args.frames})")
    return 0


if __name__ == "__main__":
    sys.exit(main())
