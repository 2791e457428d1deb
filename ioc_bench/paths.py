"""What a path may be: one policy for every path a command or the API reads or writes.

Applied before any work: a path is text (not empty, no NUL, names of at most 255 bytes, at
most 4095 bytes in all), resolves without a symbolic-link loop, lies outside the kernel's
pseudo-file systems (/proc, /sys, /dev, ...), and is what it is used as: a folder one can
write in (checked by making an unnamed file there: as root ``os.access`` says yes to
everything), a regular file (never a FIFO, device or folder) to read, within a size limit.
Paths inside a tree (result files under --out) must not lead out of it through links. A
bad path is a :class:`PathError` (a ``ValueError``) with a one-line message. Writing the
files themselves is :mod:`ioc_bench.fileio`'s.
"""

from __future__ import annotations

import errno
import functools
import os
import re
import stat
import tempfile
from pathlib import Path
from typing import Any

from ioc_bench.fileio import TEMP_SUFFIX
from ioc_bench.validation import shown

#: Longest file name (bytes) of the usual Linux file systems.
MAX_NAME_BYTES = 255
#: Characters of a path a message shows (its start and its end).
SHOWN_PATH = 80
#: Longest path (bytes) a system call takes: PATH_MAX less the closing NUL.
MAX_PATH_BYTES = 4095
#: File systems the kernel makes up: never a place for a file of ours.
PSEUDO_FILESYSTEMS = frozenset(
    {
        "proc", "sysfs", "devtmpfs", "devpts", "cgroup", "cgroup2", "debugfs", "tracefs", "securityfs",
        "configfs", "fusectl", "bpf", "pstore", "efivarfs", "mqueue", "binfmt_misc", "nsfs", "selinuxfs",
        "autofs", "rpc_pipefs", "hugetlbfs",
    }
)  # fmt: skip
#: Folders refused even where the mount table cannot be read (or /dev is a plain tmpfs, as
#: in containers); ``/dev/shm`` is scratch space and allowed.
PSEUDO_ROOTS = ("/proc", "/sys", "/dev")
_SCRATCH_ROOTS = ("/dev/shm",)


class PathError(ValueError):
    """A path that cannot serve for what it was given (the message names it and says why)."""


def check_path_text(path: Any, what: str = "the path") -> Path:
    """``path`` as a :class:`Path` if it is usable text; else :class:`PathError`.

    Refused: anything but ``str``/``os.PathLike``, the empty string (``Path("")`` would be
    the current folder), a NUL character, a name over :data:`MAX_NAME_BYTES` bytes, a path
    over :data:`MAX_PATH_BYTES` bytes.
    """
    if isinstance(path, (bytes, bytearray)) or not isinstance(path, (str, os.PathLike)):
        raise PathError(f"{what} must be a str or os.PathLike, got {type(path).__name__}")
    text = os.fspath(path)
    if isinstance(text, bytes):
        text = os.fsdecode(text)
    if text == "":
        raise PathError(f"{what} is an empty string (say '.' for the current folder)")
    named = f"{what} {shown(text, SHOWN_PATH)}"
    if "\0" in text:
        raise PathError(f"{named} contains a NUL character")
    try:
        raw = os.fsencode(text)
    except UnicodeEncodeError:
        raise PathError(f"{named} cannot be encoded as a file name") from None
    if len(raw) > MAX_PATH_BYTES:
        raise PathError(f"{named} is {len(raw)} bytes long, over the {MAX_PATH_BYTES} a path may have")
    for name in raw.split(b"/"):
        if len(name) > MAX_NAME_BYTES:
            raise PathError(f"{named} has a name of {len(name)} bytes, over the {MAX_NAME_BYTES} a file name may have")
    return Path(text)


def check_output_dir(path: Any) -> Path:
    """``path`` if it is, or can be created as, a folder to write in; else :class:`PathError`.

    Nothing is left behind: this is the check commands make before their work, so that an
    output location under a file, under ``/proc``, through a link loop, with too long a
    name, or on a read-only file system is refused before the work and not after it.
    """
    path = check_path_text(path)
    existing, tail = _locate(path)
    _refuse_pseudo(path, _real(existing).joinpath(*tail))
    if not tail:
        if not existing.is_dir():
            raise PathError(f"{path} exists and is not a directory")
        _check_writable(existing, f"{path} is not writable")
        return path
    if not existing.is_dir():
        raise PathError(f"cannot create {path}: {existing} is not a directory")
    _check_writable(existing, f"cannot create {path}: {existing} is not writable")
    return path


def check_output_file(path: Any) -> Path:
    """``path`` if a file can be written there (its folder exists or can be made); else :class:`PathError`.

    An existing ``path`` must be a regular file (it is replaced, never written through);
    a folder, FIFO or device is refused.
    """
    path = check_path_text(path)
    if path.name in ("", ".", ".."):
        raise PathError(f"{path} names a directory, not a file")
    existing, tail = _locate(path)
    _refuse_pseudo(path, _real(existing).joinpath(*tail))
    if not tail:
        mode = os.stat(existing).st_mode
        if stat.S_ISDIR(mode):
            raise PathError(f"{path} is a directory, not a file name")
        if not stat.S_ISREG(mode):
            raise PathError(f"{path} is {_kind(mode)}, not a regular file")
    elif not existing.is_dir():
        raise PathError(f"cannot create {path}: {existing} is not a directory")
    check_output_dir(path.parent)
    return path


def _stat_input(path: Path, what: str) -> os.stat_result:
    """The status of an input path that exists, is readable and is on no pseudo-file system."""
    try:
        st = os.stat(path)
    except (FileNotFoundError, NotADirectoryError):
        raise PathError(f"{what} not found: {path}") from None
    except OSError as exc:
        raise PathError(f"cannot read {what} {path}: {_reason(exc)}") from None
    _refuse_pseudo(path, _real(path))
    return st


def check_input_file(path: Any, what: str = "file", max_bytes: int | None = None) -> Path:
    """``path`` if it is a regular file to read (of at most ``max_bytes``); else :class:`PathError`."""
    path = check_path_text(path, f"the path of the {what}")
    st = _stat_input(path, what)
    if stat.S_ISDIR(st.st_mode):
        raise PathError(f"{path} is a directory, not a {what}")
    if not stat.S_ISREG(st.st_mode):
        raise PathError(f"{path} is {_kind(st.st_mode)}, not a regular file")
    if max_bytes is not None and st.st_size > max_bytes:
        raise PathError(f"{path} is {st.st_size} bytes, over the {max_bytes} a {what} may have")
    return path


def check_input_dir(path: Any, what: str = "directory") -> Path:
    """``path`` if it is a folder to read from; else :class:`PathError`."""
    path = check_path_text(path, f"the path of the {what}")
    st = _stat_input(path, what)
    if not stat.S_ISDIR(st.st_mode):
        raise PathError(f"{path} is {_kind(st.st_mode)}, not a {what}")
    return path


def check_inside(root: str | os.PathLike, path: str | os.PathLike) -> Path:
    """``path`` if, with every link followed, it lies inside ``root``; else :class:`PathError`.

    ``path`` need not exist (its existing part is resolved). For paths made of a trusted
    root and names from elsewhere (an algorithm folder, a file name from a result).
    """
    root_real = _real(Path(root))
    existing, tail = _locate(Path(path))
    real = _real(existing).joinpath(*tail)
    if real != root_real and root_real not in real.parents:
        raise PathError(f"{path} leads out of {root} (to {real})")
    return Path(path)


def read_bytes(path: str | os.PathLike, max_bytes: int, what: str = "file", follow_symlinks: bool = True) -> bytes:
    """The content of the regular file ``path`` (at most ``max_bytes``); else :class:`PathError`.

    Opened without blocking (a FIFO never hangs the reader) and checked on the open file
    (``fstat``) before reading: FIFOs, devices (``/dev/zero``), folders and files over the
    limit are refused, as are symbolic links when ``follow_symlinks`` is False.
    """
    if not follow_symlinks and os.path.islink(check_path_text(path, f"the path of the {what}")):
        raise PathError(f"{path} is a symbolic link; a {what} must be a regular file")
    path = check_input_file(path, what)  # a clear message before opening anything (opening a device can act)
    flags = os.O_RDONLY | os.O_NONBLOCK | getattr(os, "O_CLOEXEC", 0)
    if not follow_symlinks:
        flags |= getattr(os, "O_NOFOLLOW", 0)
    try:
        fd = os.open(path, flags)
    except OSError as exc:
        if not follow_symlinks and path.is_symlink():
            raise PathError(f"{path} is a symbolic link; a {what} must be a regular file") from None
        raise PathError(f"cannot read {what} {path}: {_reason(exc)}") from None
    try:
        st = os.fstat(fd)
        if not stat.S_ISREG(st.st_mode):
            raise PathError(f"{path} is {_kind(st.st_mode)}, not a regular file")
        if st.st_size > max_bytes:
            raise PathError(f"{path} is {st.st_size} bytes, over the {max_bytes} a {what} may have")
        chunks, total = [], 0
        while total <= max_bytes:
            chunk = os.read(fd, min(1 << 20, max_bytes + 1 - total))
            if not chunk:
                break
            chunks.append(chunk)
            total += len(chunk)
    except OSError as exc:
        raise PathError(f"cannot read {what} {path}: {_reason(exc)}") from None
    finally:
        os.close(fd)
    if total > max_bytes:
        raise PathError(f"{path} holds over {max_bytes} bytes, the most a {what} may have")
    return b"".join(chunks)


def check_file_name(name: Any, what: str = "file name") -> str:
    """``name`` if it is a plain file name made of letters, digits and ``-._+``; else :class:`PathError`.

    For names built from content (an algorithm's name in a figure's file name): no
    separators, no ``..``, no leading dot, at most :data:`MAX_NAME_BYTES` bytes.
    """
    if (
        not isinstance(name, str)
        or not _SAFE_NAME.fullmatch(name)
        or ".." in name
        or len(name.encode()) > MAX_NAME_BYTES
    ):
        raise PathError(f"unsafe {what} {shown(str(name), SHOWN_PATH)}: use letters, digits and -._+ (no leading dot)")
    return name


_SAFE_NAME = re.compile(r"[A-Za-z0-9_+-][A-Za-z0-9._+-]*")


def _locate(path: Path) -> tuple[Path, tuple[str, ...]]:
    """The longest existing part of ``path`` (as given) and the names below it.

    Raises :class:`PathError` for a link loop, a link to nothing, or ``..`` below a
    missing folder; a file where a folder is needed is left to the caller (the existing
    part is that file).
    """
    existing, tail = path, []
    while True:
        try:
            os.lstat(existing)
            break
        except (FileNotFoundError, NotADirectoryError):
            if existing == existing.parent:
                break
            tail.insert(0, existing.name)
            existing = existing.parent
        except OSError as exc:
            raise PathError(f"cannot use {path}: {_reason(exc)}") from None
    if ".." in tail:
        raise PathError(f"cannot use {path}: '..' below {existing / tail[0]}, which does not exist")
    try:
        os.stat(existing)
    except FileNotFoundError:
        raise PathError(f"cannot use {path}: {existing} is a symbolic link to nothing") from None
    except OSError as exc:
        where = "" if existing == path else f" at {existing}"
        raise PathError(f"cannot use {path}: {_reason(exc)}{where}") from None
    return existing, tuple(tail)


def _real(path: Path) -> Path:
    """``path`` (existing) with every link followed, absolute."""
    try:
        return Path(os.path.realpath(path, strict=True))
    except OSError as exc:
        raise PathError(f"cannot use {path}: {_reason(exc)}") from None


def _refuse_pseudo(path: Path, real: Path) -> None:
    where = pseudo_filesystem(real)
    if where:
        shown = f"{path}" if str(path) == str(real) else f"{path} ({real})"
        raise PathError(f"{shown} is under {where}, not a place for files")


def pseudo_filesystem(real: str | os.PathLike) -> str | None:
    """Where the absolute, resolved path ``real`` lies on a kernel pseudo-file system, or None."""
    text = os.fspath(real)
    if any(_under(text, root) for root in _SCRATCH_ROOTS):
        return None
    mount, fstype = "", ""
    for point, kind in _mounts():
        if _under(text, point) and len(point) >= len(mount):
            mount, fstype = point, kind
    if fstype in PSEUDO_FILESYSTEMS:
        return f"{mount} (a {fstype} file system)"
    root = next((r for r in PSEUDO_ROOTS if _under(text, r)), None)
    return f"{root} (a pseudo-file system)" if root else None


def _under(text: str, root: str) -> bool:
    return text == root or text.startswith(root.rstrip("/") + "/")


@functools.lru_cache(maxsize=1)
def _mounts() -> tuple[tuple[str, str], ...]:
    """(mount point, file system type) of every mount, from ``/proc/self/mountinfo`` (empty if unreadable)."""
    try:
        text = Path("/proc/self/mountinfo").read_text()
    except OSError:
        return ()
    mounts = []
    for line in text.splitlines():
        left, sep, right = line.partition(" - ")
        fields = left.split()
        if sep and len(fields) > 4 and right.split():
            point = re.sub(r"\\([0-7]{3})", lambda m: chr(int(m.group(1), 8)), fields[4])
            mounts.append((point, right.split()[0]))
    return tuple(mounts)


def _check_writable(directory: Path, message: str) -> None:
    """Make (and drop) an unnamed file in ``directory``; :class:`PathError` with ``message`` if it fails."""
    flag = getattr(os, "O_TMPFILE", None)
    try:
        if flag is not None:
            try:
                os.close(os.open(directory, flag | os.O_WRONLY | getattr(os, "O_CLOEXEC", 0), 0o600))
                return
            except OSError as exc:
                if exc.errno not in (errno.EOPNOTSUPP, errno.EISDIR, errno.EINVAL):
                    raise
        fd, name = tempfile.mkstemp(dir=directory, prefix=".ioc-bench-probe.", suffix=TEMP_SUFFIX)
        os.close(fd)
        os.unlink(name)
    except OSError as exc:
        raise PathError(f"{message} ({_reason(exc)})") from None


def _kind(mode: int) -> str:
    kinds = [
        (stat.S_ISDIR, "a directory"),
        (stat.S_ISFIFO, "a FIFO"),
        (stat.S_ISCHR, "a character device"),
        (stat.S_ISBLK, "a block device"),
        (stat.S_ISSOCK, "a socket"),
        (stat.S_ISLNK, "a symbolic link"),
    ]
    return next((name for test, name in kinds if test(mode)), "not a regular file")


def _reason(exc: OSError) -> str:
    if exc.errno == errno.ELOOP:
        return "a symbolic link loop"
    return exc.strerror or str(exc)
