"""Where solved things are kept between runs: ``$IOC_BENCH_CACHE`` or ``~/.cache/ioc-bench``.

Demonstrations, the references of observations and the human track's reference steps are
solved once and kept here, each kind in its own folder, every entry written atomically and
checked against the key it is filed under when it is read back.
"""

from __future__ import annotations

import os
from pathlib import Path

from ioc_bench.paths import check_output_dir


def cache_dir() -> Path:
    """``$IOC_BENCH_CACHE``, or ``~/.cache/ioc-bench``; ``ValueError`` if the variable is set but empty."""
    value = os.environ.get("IOC_BENCH_CACHE")
    if value == "":
        raise ValueError("IOC_BENCH_CACHE is set but empty: unset it or name a folder for the demonstration cache")
    return Path(value) if value is not None else Path.home() / ".cache" / "ioc-bench"


def check_cache() -> Path:
    """The cache's folder of demonstrations if it can be used, else ``ValueError`` (one line):
    checked before the work, not when the first demonstration is saved."""
    try:
        return check_output_dir(cache_dir() / "demos")
    except ValueError as exc:
        raise ValueError(
            f"the demonstration cache (IOC_BENCH_CACHE or ~/.cache/ioc-bench) cannot be used: {exc}"
        ) from None
