"""Figure helpers shared by every plot."""

from __future__ import annotations

import io
import os
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt

from ioc_bench.fileio import atomic_write

#: One colour per cost feature, reused across every figure.
FEATURE_COLORS = {
    "hip": "tab:blue",
    "knee": "tab:orange",
    "dtau": "tab:green",
    "torso": "tab:purple",
    "steplen": "tab:brown",
    "footheight": "tab:pink",
}


def save_figure(fig: plt.Figure, path: str | os.PathLike, dpi: int = 120) -> Path:
    """Save ``fig`` to ``path`` atomically (format from the suffix) and close it."""
    path = Path(path)
    buf = io.BytesIO()
    fig.savefig(buf, format=path.suffix.lstrip(".") or "png", dpi=dpi, bbox_inches="tight")
    plt.close(fig)
    return atomic_write(path, lambda f: f.write(buf.getvalue()))
