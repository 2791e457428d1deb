"""Where solved things are kept between runs: ``$IOC_BENCH_CACHE``; else
``$XDG_CACHE_HOME/ioc-bench`` when that is an absolute path; else ``~/.cache/ioc-bench``.

Demonstrations, the references of observations and the human track's reference steps are
solved once and kept here, each kind in its own folder, every entry written atomically and
checked against the key it is filed under when it is read back.
"""

from __future__ import annotations

import hashlib
import json
import os
from functools import cached_property
from pathlib import Path
from typing import Any, ClassVar

from ioc_bench.paths import check_output_dir

#: Hex digits of a cached input's key.
KEY_LENGTH = 20

#: Where the cache is looked for, in order (for messages).
WHERE = "IOC_BENCH_CACHE, else XDG_CACHE_HOME/ioc-bench, else ~/.cache/ioc-bench"


def cache_dir() -> Path:
    """``$IOC_BENCH_CACHE``; else ``$XDG_CACHE_HOME/ioc-bench`` if that variable is an absolute
    path (the XDG Base Directory specification ignores an empty or relative one); else
    ``~/.cache/ioc-bench``. ``ValueError`` if ``IOC_BENCH_CACHE`` is set but empty."""
    value = os.environ.get("IOC_BENCH_CACHE")
    if value == "":
        raise ValueError("IOC_BENCH_CACHE is set but empty: unset it or name a folder for the demonstration cache")
    if value is not None:
        return Path(value)
    xdg = os.environ.get("XDG_CACHE_HOME", "")
    if os.path.isabs(xdg):
        return Path(xdg) / "ioc-bench"
    return Path.home() / ".cache" / "ioc-bench"


def check_cache() -> Path:
    """The cache's folder of demonstrations if it can be used, else ``ValueError`` (one line):
    checked before the work, not when the first demonstration is saved."""
    try:
        return check_output_dir(cache_dir() / "demos")
    except ValueError as exc:
        raise ValueError(f"the demonstration cache ({WHERE}) cannot be used: {exc}") from None


class CachedInput:
    """Something solved once and kept in the cache (a demonstration, a human reference step),
    named by its key: a hash of what it depends on (:meth:`payload`) and of its kind's
    :attr:`revision`, which a change to how it is solved raises. Two are equal when their
    keys are, so cases that need the same input share one solve. A kind gives
    :meth:`payload`, :attr:`revision` and :meth:`prepare`."""

    revision: ClassVar[int]

    def payload(self) -> dict[str, Any]:
        """Every input the solved thing depends on, as JSON values."""
        raise NotImplementedError

    def prepare(self) -> Any:
        """The solved thing: from the cache if its entry is this key's, else solved and kept."""
        raise NotImplementedError

    @cached_property
    def key(self) -> str:
        payload = self.payload() | {"revision": self.revision}
        return hashlib.sha256(json.dumps(payload, sort_keys=True).encode()).hexdigest()[:KEY_LENGTH]

    def __eq__(self, other: object) -> bool:
        return type(other) is type(self) and self.key == other.key

    def __hash__(self) -> int:
        return hash(self.key)
