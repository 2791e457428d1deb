"""Software drawing of the walker: stick figures rasterised with matplotlib's Agg backend.

Used for the replay GIF (always) and as the environment's ``rgb_array`` fallback when no
OpenGL backend is available (a pip-only CI machine has neither EGL nor OSMesa for sure).
Needs nothing beyond matplotlib and Pillow (a matplotlib dependency).
"""

from __future__ import annotations

import io
import os
from collections.abc import Sequence
from pathlib import Path

import numpy as np
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure

from ioc_bench.fileio import atomic_write
from ioc_bench.model.params import WalkerParams

#: Colours of the torso and legs a and b (the MJCF's colours).
COLORS = {"torso": "#333333", "a": "#d93333", "b": "#3359d9"}


def stick_points(params: WalkerParams, qpos: np.ndarray) -> dict[str, np.ndarray]:
    """World (x, z) polylines of the torso (hip, shoulder) and each leg (hip, knee, foot)."""
    hip = np.asarray(qpos[:2], dtype=float)
    torso = float(qpos[2])

    def axis(theta: float) -> np.ndarray:
        return np.array([np.sin(theta), np.cos(theta)])

    out = {"torso": np.stack([hip, hip + params.torso.length * axis(torso)])}
    for leg, (i_hip, i_knee) in {"a": (3, 4), "b": (5, 6)}.items():
        thigh = torso + float(qpos[i_hip])
        knee = hip - params.thigh.length * axis(thigh)
        foot = knee - params.shank.length * axis(thigh + float(qpos[i_knee]))
        out[leg] = np.stack([hip, knee, foot])
    return out


class StickRenderer:
    """Draws the walker as a stick figure into an RGB array, the camera following the hip.

    Args:
        params: the walker (segment lengths).
        width, height: image size in pixels.
        heights: (bottom, top) of the visible world, in leg lengths; the visible width
            follows from the image's aspect ratio.
    """

    def __init__(
        self, params: WalkerParams, width: int = 480, height: int = 360, heights: tuple[float, float] = (-0.1, 1.8)
    ):
        self.params = params
        self.heights = heights
        self.half_width = 0.5 * (heights[1] - heights[0]) * width / height
        self.fig = Figure(figsize=(width / 100, height / 100), dpi=100)
        self.canvas = FigureCanvasAgg(self.fig)
        ax = self.fig.add_axes((0, 0, 1, 1))
        ax.set_aspect("equal")
        ax.axis("off")
        ax.axhline(0.0, color="#888888", lw=1.5)
        self.ticks = ax.plot([], [], "|", color="#888888", ms=6)[0]
        self.lines = {name: ax.plot([], [], "-o", color=c, lw=3, ms=3)[0] for name, c in COLORS.items()}
        self.text = ax.text(0.02, 0.97, "", transform=ax.transAxes, va="top", fontsize=8)
        self.ax = ax

    def render(self, qpos: np.ndarray, label: str = "") -> np.ndarray:
        """(height, width, 3) uint8 image of the walker at ``qpos``."""
        for name, pts in stick_points(self.params, qpos).items():
            self.lines[name].set_data(pts[:, 0], pts[:, 1])
        cx, half = float(qpos[0]), self.half_width
        self.ax.set_xlim(cx - half, cx + half)
        self.ax.set_ylim(*self.heights)
        marks = np.arange(np.floor(cx - half), np.ceil(cx + half) + 0.01, 0.25)
        self.ticks.set_data(marks, np.zeros_like(marks))
        self.text.set_text(label)
        self.canvas.draw()
        return np.asarray(self.canvas.buffer_rgba())[:, :, :3].copy()

    def close(self) -> None:
        self.fig.clear()


def write_gif(path: str | os.PathLike, frames: Sequence[np.ndarray], fps: float) -> Path:
    """Write RGB frames as a looping GIF, atomically."""
    from PIL import Image

    if not frames:
        raise ValueError("no frames to write")
    images = [Image.fromarray(f) for f in frames]
    buf = io.BytesIO()
    images[0].save(
        buf, format="GIF", save_all=True, append_images=images[1:], duration=round(1000 / fps), loop=0, optimize=False
    )
    return atomic_write(path, lambda f: f.write(buf.getvalue()))
