"""Headless matplotlib and atomic figure files: what every plot of the package draws with.

Importing this module selects matplotlib's Agg backend (no display needed) before
``pyplot`` is loaded; :func:`save_figure` writes a figure in one step
(:func:`ioc_bench.fileio.atomic_write`), so a figure on disk is never half-written. It sits
at the package's base, beside :mod:`ioc_bench.fileio`, so that the synthetic benchmark's
figures (:mod:`ioc_bench.viz`), the human track's (:mod:`ioc_bench.human.figures`) and the
replay's (:mod:`envs.plots`) share it without importing one another.
"""

from __future__ import annotations

import io
import os
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # after the backend is chosen

from ioc_bench.fileio import atomic_write

__all__ = ["plt", "save_figure"]


def save_figure(fig: plt.Figure, path: str | os.PathLike, dpi: int = 120) -> Path:
    """Save ``fig`` to ``path`` atomically (format from the suffix) and close it."""
    path = Path(path)
    buf = io.BytesIO()
    fig.savefig(buf, format=path.suffix.lstrip(".") or "png", dpi=dpi, bbox_inches="tight")
    plt.close(fig)
    return atomic_write(path, lambda f: f.write(buf.getvalue()))
