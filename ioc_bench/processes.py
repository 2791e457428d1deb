"""Worker processes that never outlive the run that started them, and never hold its locks.

Every worker ioc-bench forks (the multi-start's solves, the local executor's cases) calls
:func:`die_with_parent` first: Linux kills it when its parent dies, however the parent
dies (``kill -9`` included), and a worker whose parent died before it could ask exits at
once. A forked child also inherits every open file of its parent, so a lock held on a
results directory would live on in it; :func:`hold_across_fork` names descriptors that
children close as soon as they are forked, so a lock lives exactly as long as the process
that took it.
"""

from __future__ import annotations

import contextlib
import ctypes
import os
import signal
import sys

#: ``prctl`` option: the signal this process gets when its parent thread dies.
_PR_SET_PDEATHSIG = 1
#: Descriptors the parent holds that its forked children must not keep.
_HELD: set[int] = set()


def die_with_parent(parent_pid: int) -> None:
    """In a freshly forked worker: be killed when the parent ``parent_pid`` dies, and exit
    now if it died already (between the fork and this call). Ctrl-C is the parent's to
    handle: the worker ignores SIGINT and is stopped by its parent."""
    if sys.platform.startswith("linux"):
        with contextlib.suppress(OSError, AttributeError):
            ctypes.CDLL("libc.so.6", use_errno=True).prctl(_PR_SET_PDEATHSIG, signal.SIGKILL)
    if os.getppid() != parent_pid:
        os._exit(1)
    signal.signal(signal.SIGINT, signal.SIG_IGN)


@contextlib.contextmanager
def hold_across_fork(fd: int):
    """While the block runs, children forked by this process close ``fd`` at once."""
    _HELD.add(fd)
    try:
        yield fd
    finally:
        _HELD.discard(fd)


def _close_held() -> None:
    for fd in list(_HELD):
        with contextlib.suppress(OSError):
            os.close(fd)
    _HELD.clear()


if hasattr(os, "register_at_fork"):
    os.register_at_fork(after_in_child=_close_held)
