"""Atomic file writes: a result file is either absent or whole, never half-written.

A file is written in full (and flushed to disk) before it gets its final name, so a reader
sees the old content or the new one, nothing in between. On Linux the content is first
written to an *unnamed* file (``O_TMPFILE``): a process killed while writing leaves
nothing behind. The unnamed file is then linked straight to its name if that name is
free, or to a temporary name (``.<name>.<random>.tmp``) that replaces the old file. Only
a kill in the instant between that link and the rename can leave a temporary; where
``O_TMPFILE`` is not available every write goes through such a temporary. Temporaries are
never read as results (:func:`is_temporary`), and :func:`remove_temporaries` deletes them
(the runner does so when it opens a results directory). Also here: the JSON text every
file of ours is written as (:func:`json_text`).

What a path may be (the checks every command and the API make before any work) is
:mod:`ioc_bench.paths`, which builds on this module (never the other way round).
"""

from __future__ import annotations

import ctypes
import errno
import json
import math
import os
import stat
import sys
import tempfile
from collections.abc import Callable, Mapping
from pathlib import Path
from typing import IO, Any

#: Suffix of the temporary files of :func:`atomic_write`.
TEMP_SUFFIX = ".tmp"
_PROC_FD = Path("/proc/self/fd")


def atomic_write(path: str | os.PathLike, write: Callable[[IO[bytes]], Any]) -> Path:
    """Call ``write(file)`` on a new file, then move it to ``path`` in one step."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    staged = _stage(path, write, link_final=True)
    if staged is not None:
        _replace(staged, path)
    return path


def atomic_write_many(contents: Mapping[str | os.PathLike, bytes]) -> list[Path]:
    """Write several files, each atomically, all contents staged before any is replaced.

    Every file is written in full before the first one is renamed into place, so an
    error while writing changes none of them. The renames follow one another at once; a
    kill in between them is the only way to leave some files old and some new.
    """
    staged: list[tuple[Path, Path]] = []
    try:
        for target, data in contents.items():
            path = Path(target)
            path.parent.mkdir(parents=True, exist_ok=True)
            tmp = _stage(path, lambda f, data=data: f.write(data), link_final=False)
            assert tmp is not None  # link_final=False always stages under a temporary name
            staged.append((tmp, path))
    except BaseException:
        for tmp, _ in staged:
            tmp.unlink(missing_ok=True)
        raise
    for i, (tmp, path) in enumerate(staged):
        try:
            _replace(tmp, path)
        except BaseException:
            for later, _ in staged[i + 1 :]:
                later.unlink(missing_ok=True)
            raise
    return [path for _, path in staged]


def atomic_write_text(path: str | os.PathLike, text: str) -> Path:
    return atomic_write(path, lambda f: f.write(text.encode()))


def atomic_write_json(path: str | os.PathLike, data: Any) -> Path:
    """Write ``data`` as JSON (numpy values converted, NaN/inf as null) atomically."""
    return atomic_write_text(path, json_text(data))


def json_text(data: Any) -> str:
    """``data`` as the JSON text :func:`atomic_write_json` writes."""
    return json.dumps(to_jsonable(data), indent=2, sort_keys=True) + "\n"


def to_jsonable(obj: Any) -> Any:
    """Convert numpy scalars/arrays and nested containers for ``json.dumps`` (NaN -> None)."""
    if isinstance(obj, dict):
        return {str(k): to_jsonable(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [to_jsonable(v) for v in obj]
    if hasattr(obj, "tolist"):  # numpy arrays and scalars
        return to_jsonable(obj.tolist())
    if isinstance(obj, float) and not math.isfinite(obj):
        return None
    return obj


def is_temporary(path: str | os.PathLike) -> bool:
    """Whether ``path`` is named like a temporary of :func:`atomic_write`."""
    name = Path(path).name
    return name.startswith(".") and name.endswith(TEMP_SUFFIX)


def remove_temporaries(directory: str | os.PathLike) -> list[Path]:
    """Delete the temporaries left in ``directory`` and its subfolders by killed writers.

    Call it only when no other process is writing there (the runner holds a lock).
    Returns the removed paths.
    """
    removed = []
    for folder, _dirs, names in os.walk(directory):  # links to folders are not followed
        for name in names:
            path = Path(folder) / name
            if is_temporary(path) and stat.S_ISREG(os.lstat(path).st_mode):
                path.unlink(missing_ok=True)
                removed.append(path)
    return removed


# -- internals -------------------------------------------------------------------------


def _stage(path: Path, write: Callable[[IO[bytes]], Any], link_final: bool) -> Path | None:
    """Write the content and give it a name: ``path`` itself (returns None, only if
    ``link_final`` and ``path`` is free) or a temporary name (returned)."""
    fd = _open_unnamed(path.parent)
    if fd is None:
        return _stage_named(path, write)
    try:
        return _name_unnamed(fd, path, write, link_final)
    except _CannotLink:  # e.g. /proc/self/fd not usable for linkat here: write again, named
        return _stage_named(path, write)


class _CannotLink(Exception):
    pass


def _name_unnamed(fd: int, path: Path, write: Callable[[IO[bytes]], Any], link_final: bool) -> Path | None:
    with os.fdopen(fd, "wb") as f:
        write(f)
        f.flush()
        os.fsync(f.fileno())
        source = _PROC_FD / str(f.fileno())
        if link_final and _link(source, path):
            return None
        for _ in range(100):
            tmp = path.parent / _temp_name(path)
            if _link(source, tmp):
                return tmp
    raise OSError(f"could not name a temporary file beside {path}")


def _link(source: Path, target: Path) -> bool:
    """Give the unnamed file ``source`` (``/proc/self/fd/N``) the name ``target``; False if taken.

    ``linkat(AT_SYMLINK_FOLLOW)`` through libc: ``os.link`` calls ``link()``, which does
    not follow the ``/proc`` link to the open file.
    """
    if _libc is None:
        raise _CannotLink("no libc linkat")
    if _libc.linkat(_AT_FDCWD, os.fsencode(source), _AT_FDCWD, os.fsencode(target), _AT_SYMLINK_FOLLOW) == 0:
        return True
    err = ctypes.get_errno()
    if err == errno.EEXIST:
        return False
    raise _CannotLink(os.strerror(err))


def _load_libc():
    try:
        libc = ctypes.CDLL(None, use_errno=True)
        libc.linkat.argtypes = [ctypes.c_int, ctypes.c_char_p, ctypes.c_int, ctypes.c_char_p, ctypes.c_int]
        return libc
    except (OSError, AttributeError):
        return None


_AT_FDCWD, _AT_SYMLINK_FOLLOW = -100, 0x400
_libc = _load_libc() if sys.platform.startswith("linux") else None


def _stage_named(path: Path, write: Callable[[IO[bytes]], Any]) -> Path:
    """The portable way: write a named temporary file beside ``path``."""
    fd, name = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=TEMP_SUFFIX)
    tmp = Path(name)
    try:
        with os.fdopen(fd, "wb") as f:
            write(f)
            f.flush()
            os.fsync(f.fileno())
        os.chmod(tmp, 0o666 & ~_umask())  # mkstemp makes files owner-only; use the usual mode
    except BaseException:
        tmp.unlink(missing_ok=True)
        raise
    return tmp


def _open_unnamed(directory: Path) -> int | None:
    """A file descriptor of a new unnamed file in ``directory``, or None where unsupported."""
    flag = getattr(os, "O_TMPFILE", None)
    if flag is None or _libc is None or not _PROC_FD.is_dir() or os.environ.get("IOC_BENCH_NAMED_TEMPORARIES"):
        return None
    try:
        return os.open(directory, flag | os.O_WRONLY | getattr(os, "O_CLOEXEC", 0), 0o666)
    except OSError:  # a file system without O_TMPFILE support
        return None


def _temp_name(path: Path) -> str:
    return f".{path.name}.{os.urandom(6).hex()}{TEMP_SUFFIX}"


def _replace(tmp: Path, path: Path) -> None:
    try:
        os.replace(tmp, path)
    except BaseException:
        tmp.unlink(missing_ok=True)
        raise


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask
