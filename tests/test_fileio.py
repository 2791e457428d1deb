"""Atomic writes: a writer killed (SIGKILL) at any point leaves the old file or the new one, whole.

Kills land *inside* ``atomic_write``: a traced child kills itself at every Python line
that ``atomic_write`` (and the ``write`` callback it runs) executes, one child per line,
and other children are killed from outside after seeded random delays while they write
large files. Both ways of staging are covered: unnamed ``O_TMPFILE`` files (the default
on Linux) and named temporaries (the portable fallback).
"""

from __future__ import annotations

import os
import signal
import sys
import time

import numpy as np
import pytest

from ioc_bench import fileio
from ioc_bench.fileio import (
    atomic_write,
    atomic_write_many,
    is_temporary,
    remove_temporaries,
)

OLD = b'{"old": true}\n' * 50
NEW = b'{"new": true}\n' * 80
CHUNK = 64


def _write_new(f) -> None:
    """The ``write`` callback: NEW in chunks, so that kills can land between chunks."""
    for i in range(0, len(NEW), CHUNK):
        f.write(NEW[i : i + CHUNK])


def _tracer(kill_at: int | None, counter: list[int]):
    """A trace function counting executed lines of fileio and of ``_write_new``; at line
    ``kill_at`` the process SIGKILLs itself."""
    watched = {fileio.__file__, _write_new.__code__.co_filename}

    def trace(frame, event, arg):
        code = frame.f_code
        if code.co_filename not in watched or (
            code.co_filename == _write_new.__code__.co_filename and code is not _write_new.__code__
        ):
            return None
        if event == "line":
            counter[0] += 1
            if counter[0] == kill_at:
                os.kill(os.getpid(), signal.SIGKILL)
        return trace

    return trace


def _lines_of_one_write(path) -> int:
    counter = [0]
    sys.settrace(_tracer(None, counter))
    try:
        atomic_write(path, _write_new)
    finally:
        sys.settrace(None)
    return counter[0]


def _fork(child) -> int:
    """Run ``child()`` in a forked process; its wait status."""
    pid = os.fork()
    if pid == 0:  # pragma: no cover - the child never returns into pytest
        code = 1
        try:
            child()
            code = 0
        finally:
            os._exit(code)
    _, status = os.waitpid(pid, 0)
    return status


def _state(directory, target) -> tuple[bytes | None, list[str]]:
    """The target's content (None if absent) and the names of every other file."""
    others = sorted(p.name for p in directory.iterdir() if p.name != target.name)
    return (target.read_bytes() if target.exists() else None), others


@pytest.fixture(params=["unnamed", "named"])
def staging(request, monkeypatch, tmp_path_factory):
    if request.param == "named":
        monkeypatch.setenv("IOC_BENCH_NAMED_TEMPORARIES", "1")
    else:
        monkeypatch.delenv("IOC_BENCH_NAMED_TEMPORARIES", raising=False)
        fd = fileio._open_unnamed(tmp_path_factory.getbasetemp())
        if fd is None:
            pytest.skip("O_TMPFILE is not available here")
        os.close(fd)
    return request.param


@pytest.mark.parametrize("existing", [False, True], ids=["first-write", "overwrite"])
def test_sigkill_at_every_line_of_a_write_leaves_old_or_new_never_half(tmp_path, staging, existing):
    probe = tmp_path / "probe" / "r.json"
    if existing:
        probe.parent.mkdir()
        probe.write_bytes(OLD)
    n = _lines_of_one_write(probe)
    assert n > 10 and probe.read_bytes() == NEW
    left_temporaries = 0
    for k in range(1, n + 1):
        d = tmp_path / f"k{k}"
        d.mkdir()
        target = d / "r.json"
        if existing:
            target.write_bytes(OLD)

        def child(k=k, target=target):
            sys.settrace(_tracer(k, [0]))
            atomic_write(target, _write_new)

        status = _fork(child)
        assert os.WIFSIGNALED(status) and os.WTERMSIG(status) == signal.SIGKILL, f"line {k} of {n} was not reached"
        content, others = _state(d, target)
        assert content in ((OLD, NEW) if existing else (None, NEW)), f"half-written file after a kill at line {k}"
        assert all(is_temporary(d / name) for name in others), others
        left_temporaries += len(others)
        remove_temporaries(d)
        assert _state(d, target) == (content, [])
    never = tmp_path / "never"
    never.mkdir()
    if existing:
        (never / "r.json").write_bytes(OLD)

    def beyond(target=never / "r.json"):
        sys.settrace(_tracer(n + 1, [0]))
        atomic_write(target, _write_new)

    assert _fork(beyond) == 0, "the count of lines is the whole write"
    if staging == "unnamed" and not existing:
        assert left_temporaries == 0  # an unnamed file is linked straight to its free name
    print(f"{staging}, {'overwrite' if existing else 'first write'}: {n} kill points, {left_temporaries} temporaries")


def test_sigkill_from_outside_at_random_moments_of_large_writes(tmp_path, staging):
    """A child rewrites one file over and over with large contents; it is killed after a
    seeded random delay, 25 times. The file is always one of the contents, whole."""
    rng = np.random.default_rng(2024)
    contents = [bytes([65 + i]) * (2_000_000 + 1000 * i) for i in range(3)]
    target = tmp_path / "big.bin"
    for trial in range(25):
        ready_r, ready_w = os.pipe()
        pid = os.fork()
        if pid == 0:  # pragma: no cover - child
            try:
                os.close(ready_r)
                os.write(ready_w, b"x")
                i = 0
                while True:
                    data = contents[i % len(contents)]
                    atomic_write(target, lambda f, data=data: f.write(data))
                    i += 1
            finally:
                os._exit(1)
        os.close(ready_w)
        os.read(ready_r, 1)
        os.close(ready_r)
        time.sleep(float(rng.uniform(0.0, 0.08)))
        os.kill(pid, signal.SIGKILL)
        os.waitpid(pid, 0)
        content, others = _state(tmp_path, target)
        assert content is None or content in contents, f"trial {trial}: a torn file"
        assert all(is_temporary(tmp_path / name) for name in others)
        remove_temporaries(tmp_path)
        assert _state(tmp_path, target)[1] == []


def test_an_error_while_writing_changes_nothing(tmp_path, staging):
    target = tmp_path / "r.json"
    target.write_bytes(OLD)

    def broken(f):
        f.write(b"partial")
        raise RuntimeError("disk full")

    with pytest.raises(RuntimeError):
        atomic_write(target, broken)
    assert _state(tmp_path, target) == (OLD, [])


def test_atomic_write_many_stages_everything_before_replacing(tmp_path, staging, monkeypatch):
    a, b = tmp_path / "README.md", tmp_path / "board.json"
    a.write_bytes(b"old a")
    b.write_bytes(b"old b")
    real = fileio._stage
    calls = []

    def failing_second(path, write, link_final):
        calls.append(path)
        if len(calls) == 2:
            raise OSError("no space left")
        return real(path, write, link_final)

    monkeypatch.setattr(fileio, "_stage", failing_second)
    with pytest.raises(OSError):
        atomic_write_many({a: b"new a", b: b"new b"})
    assert (a.read_bytes(), b.read_bytes()) == (b"old a", b"old b")  # not a mixed pair
    assert sorted(p.name for p in tmp_path.iterdir()) == ["README.md", "board.json"]
    monkeypatch.setattr(fileio, "_stage", real)
    assert atomic_write_many({a: b"new a", b: b"new b"}) == [a, b]
    assert (a.read_bytes(), b.read_bytes()) == (b"new a", b"new b")


def test_written_files_get_the_usual_mode(tmp_path, staging):
    path = atomic_write(tmp_path / "x", lambda f: f.write(b"1"))
    mask = os.umask(0)
    os.umask(mask)
    assert path.stat().st_mode & 0o777 == 0o666 & ~mask


# -- several files at once, and temporaries --------------------------------------------------


def test_atomic_write_many_leaves_no_temporary_when_a_rename_fails(tmp_path, staging):
    """README.md being a folder: the rename fails, and leaderboard.json's temporary is removed too."""
    (tmp_path / "README.md").mkdir()
    with pytest.raises(OSError):
        atomic_write_many({tmp_path / "README.md": b"md", tmp_path / "leaderboard.json": b"{}"})
    assert sorted(p.name for p in tmp_path.iterdir()) == ["README.md"]  # no temporary, no half board
    (tmp_path / "README.md").rmdir()
    (tmp_path / "b").mkdir()
    with pytest.raises(OSError):
        atomic_write_many({tmp_path / "a": b"a", tmp_path / "b": b"b", tmp_path / "c": b"c"})
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a", "b"]  # a renamed before b failed; c dropped


def test_remove_temporaries_never_follows_links(tmp_path):
    outside = tmp_path / "outside"
    outside.mkdir()
    kept = outside / ".x.json.abc.tmp"
    kept.write_text("{")
    root = tmp_path / "root"
    root.mkdir()
    (root / "linked").symlink_to(outside)
    (root / ".y.json.def.tmp").write_text("{")
    assert remove_temporaries(root) == [root / ".y.json.def.tmp"]
    assert kept.exists()
