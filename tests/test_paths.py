"""What a path may be (:mod:`ioc_bench.paths`): outputs that would fail after the work, inputs
that are not regular files, paths that leave their tree, names built from content."""

from __future__ import annotations

import os

import pytest

from ioc_bench import paths
from ioc_bench.paths import check_output_dir, check_output_file


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
    with pytest.raises(paths.PathError, match=message) as exc:
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
    with pytest.raises(paths.PathError, match=message):
        check_output_file(path)


def test_good_output_locations_pass(odd_files):
    assert check_output_dir(odd_files / "new" / "deep") == odd_files / "new" / "deep"
    assert check_output_file(odd_files / "file") == odd_files / "file"  # replaced, never written through
    assert check_output_file(odd_files / "inside" / "new.json") == odd_files / "inside" / "new.json"
    assert check_output_dir(odd_files / "out")  # a link the user gave is followed
    assert not (odd_files / "new").exists()


def test_read_bytes_opens_regular_files_only_within_a_limit(odd_files):
    """/dev/zero would exhaust memory and a FIFO would block the reader forever: both are refused."""
    assert paths.read_bytes(odd_files / "file", 10) == b"x"
    refused = {
        odd_files / "fifo": "is a FIFO",  # would block a plain open() forever
        "/dev/zero": "under /dev",
        odd_files / "inside": "is a directory",
        odd_files / "loop": "symbolic link loop",
        odd_files / "nope": "file not found",
        odd_files / "to-proc": "under /proc",
    }
    for path, message in refused.items():
        with pytest.raises(paths.PathError, match=message):
            paths.read_bytes(path, 10)
    (odd_files / "big").write_bytes(b"x" * 11)
    with pytest.raises(paths.PathError, match="11 bytes, over the 10"):
        paths.read_bytes(odd_files / "big", 10)
    (odd_files / "link").symlink_to(odd_files / "file")
    assert paths.read_bytes(odd_files / "link", 10) == b"x"
    with pytest.raises(paths.PathError, match="is a symbolic link"):
        paths.read_bytes(odd_files / "link", 10, follow_symlinks=False)


def test_paths_inside_a_tree_must_stay_inside_it(odd_files):
    assert paths.check_inside(odd_files, odd_files / "inside" / "x.json")
    assert paths.check_inside(odd_files, odd_files / "inside" / ".." / "file")
    for escaping in ("out/x", "to-proc", "inside/../../x"):
        with pytest.raises(paths.PathError, match="leads out of"):
            paths.check_inside(odd_files, odd_files / escaping)


def test_names_built_from_content_are_plain_names():
    assert paths.check_file_name("figure4_log-barrier__cfg1234abcd.png")
    for name in ("x/../../ESCAPED", "..", ".hidden", "a b", "", "n" * 256, None, "a\\b"):
        with pytest.raises(paths.PathError, match="unsafe"):
            paths.check_file_name(name)


def test_pseudo_file_systems_are_found_from_the_mount_table():
    assert "proc" in paths.pseudo_filesystem("/proc/self/status")
    assert "sysfs" in paths.pseudo_filesystem("/sys/kernel")
    assert paths.pseudo_filesystem("/dev/zero") is not None
    assert paths.pseudo_filesystem("/dev/shm/x") is None  # scratch space
    assert paths.pseudo_filesystem("/tmp/x") is None
    assert paths.pseudo_filesystem("/processes") is None  # a prefix of a name is not a folder


def test_a_read_only_or_unwritable_folder_is_refused_by_trying(tmp_path, monkeypatch):
    """As root ``os.access`` says yes to everything: the check makes an unnamed file instead."""
    real_open = os.open

    def denied(path, flags, *args):
        if str(path) == str(tmp_path) and flags & getattr(os, "O_TMPFILE", 0):
            raise PermissionError(13, "Permission denied")
        return real_open(path, flags, *args)

    monkeypatch.setattr(os, "open", denied)
    with pytest.raises(paths.PathError, match="is not writable"):
        check_output_dir(tmp_path)
    with pytest.raises(paths.PathError, match=r"cannot create .* is not writable"):
        check_output_dir(tmp_path / "sub")
