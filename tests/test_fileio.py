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
    check_output_dir,
    check_output_file,
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


def test_output_checks_refuse_locations_under_files(tmp_path):
    a_file = tmp_path / "file"
    a_file.write_text("x")
    with pytest.raises(ValueError, match="is not a directory"):
        check_output_dir(a_file / "sub" / "dir")
    with pytest.raises(ValueError, match="exists and is not a directory"):
        check_output_dir(a_file)
    with pytest.raises(ValueError, match="is a directory"):
        check_output_file(tmp_path)
    with pytest.raises(ValueError, match="is not a directory"):
        check_output_file(a_file / "x.json")
    assert check_output_dir(tmp_path / "new" / "deep") == tmp_path / "new" / "deep"
    assert not (tmp_path / "new").exists()  # a check creates nothing


# -- what a path may be --------------------------------------------------------------------------


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


@pytest.fixture
def odd_files(tmp_path):
    """A folder with a file, a FIFO, a link loop, a dangling link and links to /proc and out."""
    (tmp_path / "file").write_text("x")
    os.mkfifo(tmp_path / "fifo")
    (tmp_path / "loop").symlink_to(tmp_path / "loop")
    (tmp_path / "dangling").symlink_to(tmp_path / "nothing")
    (tmp_path / "to-proc").symlink_to("/proc/self")
    (tmp_path / "inside").mkdir()
    (tmp_path / "out").symlink_to(tmp_path.parent)
    return tmp_path


@pytest.mark.parametrize(
    ("relative", "message"),
    [
        ("", "empty string"),
        ("a\0b", "NUL character"),
        ("n" * 256, "over the 255 a file name may have"),
        ("/".join(["d" * 250] * 17), "over the 4095 a path may have"),
        ("/proc/ioc-bench", "under /proc"),
        ("/sys/kernel/x", "under /sys"),
        ("/dev/ioc-bench", "under /dev"),
        ("to-proc/x", "under /proc"),
        ("loop", "symbolic link loop"),
        ("loop/x", "symbolic link loop"),
        ("dangling", "symbolic link to nothing"),
        ("file", "exists and is not a directory"),
        ("file/x", "file is not a directory"),
        ("fifo", "exists and is not a directory"),
        ("missing/../x", "'..' below"),
    ],
)
def test_output_dirs_that_would_fail_after_the_work_are_refused(odd_files, relative, message):
    before = sorted(p.name for p in odd_files.iterdir())
    path = relative if relative.startswith("/") or not relative else str(odd_files / relative)
    with pytest.raises(fileio.PathError, match=message) as exc:
        check_output_dir(path)
    assert "\n" not in str(exc.value)
    assert sorted(p.name for p in odd_files.iterdir()) == before  # a check creates nothing


@pytest.mark.parametrize(
    ("relative", "message"),
    [
        ("", "empty string"),
        (".", "names a directory"),
        ("inside", "is a directory"),
        ("fifo", "is a FIFO, not a regular file"),
        ("/dev/null", "under /dev"),
        ("/proc/self/x.json", "under /proc"),
        ("loop", "symbolic link loop"),
        ("file/r.json", "file is not a directory"),
        ("n" * 256 + ".json", "over the 255"),
    ],
)
def test_output_files_that_would_fail_after_the_work_are_refused(odd_files, relative, message):
    path = relative if relative.startswith("/") or relative in ("", ".") else str(odd_files / relative)
    with pytest.raises(fileio.PathError, match=message):
        check_output_file(path)


def test_good_output_locations_pass(odd_files):
    assert check_output_dir(odd_files / "new" / "deep") == odd_files / "new" / "deep"
    assert check_output_file(odd_files / "file") == odd_files / "file"  # replaced, never written through
    assert check_output_file(odd_files / "inside" / "new.json") == odd_files / "inside" / "new.json"
    assert check_output_dir(odd_files / "out")  # a link the user gave is followed
    assert not (odd_files / "new").exists()


def test_read_bytes_opens_regular_files_only_within_a_limit(odd_files):
    """/dev/zero would exhaust memory and a FIFO would block the reader forever: both are refused."""
    assert fileio.read_bytes(odd_files / "file", 10) == b"x"
    refused = {
        odd_files / "fifo": "is a FIFO",  # would block a plain open() forever
        "/dev/zero": "under /dev",
        odd_files / "inside": "is a directory",
        odd_files / "loop": "symbolic link loop",
        odd_files / "nope": "file not found",
        odd_files / "to-proc": "under /proc",
    }
    for path, message in refused.items():
        with pytest.raises(fileio.PathError, match=message):
            fileio.read_bytes(path, 10)
    (odd_files / "big").write_bytes(b"x" * 11)
    with pytest.raises(fileio.PathError, match="11 bytes, over the 10"):
        fileio.read_bytes(odd_files / "big", 10)
    (odd_files / "link").symlink_to(odd_files / "file")
    assert fileio.read_bytes(odd_files / "link", 10) == b"x"
    with pytest.raises(fileio.PathError, match="is a symbolic link"):
        fileio.read_bytes(odd_files / "link", 10, follow_symlinks=False)


def test_paths_inside_a_tree_must_stay_inside_it(odd_files):
    assert fileio.check_inside(odd_files, odd_files / "inside" / "x.json")
    assert fileio.check_inside(odd_files, odd_files / "inside" / ".." / "file")
    for escaping in ("out/x", "to-proc", "inside/../../x"):
        with pytest.raises(fileio.PathError, match="leads out of"):
            fileio.check_inside(odd_files, odd_files / escaping)


def test_names_built_from_content_are_plain_names():
    assert fileio.check_file_name("figure4_log-barrier__cfg1234abcd.png")
    for name in ("x/../../ESCAPED", "..", ".hidden", "a b", "", "n" * 256, None, "a\\b"):
        with pytest.raises(fileio.PathError, match="unsafe"):
            fileio.check_file_name(name)


def test_pseudo_file_systems_are_found_from_the_mount_table():
    assert "proc" in fileio.pseudo_filesystem("/proc/self/status")
    assert "sysfs" in fileio.pseudo_filesystem("/sys/kernel")
    assert fileio.pseudo_filesystem("/dev/zero") is not None
    assert fileio.pseudo_filesystem("/dev/shm/x") is None  # scratch space
    assert fileio.pseudo_filesystem("/tmp/x") is None
    assert fileio.pseudo_filesystem("/processes") is None  # a prefix of a name is not a folder


def test_a_read_only_or_unwritable_folder_is_refused_by_trying(tmp_path, monkeypatch):
    """As root ``os.access`` says yes to everything: the check makes an unnamed file instead."""
    real_open = os.open

    def denied(path, flags, *args):
        if str(path) == str(tmp_path) and flags & getattr(os, "O_TMPFILE", 0):
            raise PermissionError(13, "Permission denied")
        return real_open(path, flags, *args)

    monkeypatch.setattr(os, "open", denied)
    with pytest.raises(fileio.PathError, match="is not writable"):
        check_output_dir(tmp_path)
    with pytest.raises(fileio.PathError, match=r"cannot create .* is not writable"):
        check_output_dir(tmp_path / "sub")


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
