"""What the benchmark's figures share beyond :mod:`ioc_bench.plotting` (headless pyplot,
atomic figure files): one colour per cost feature."""

from __future__ import annotations

#: One colour per cost feature, reused across every figure.
FEATURE_COLORS = {
    "hip": "tab:blue",
    "knee": "tab:orange",
    "dtau": "tab:green",
    "torso": "tab:purple",
    "steplen": "tab:brown",
    "footheight": "tab:pink",
}
