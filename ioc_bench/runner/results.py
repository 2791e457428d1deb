"""Result files: one JSON per case, named by the case, written atomically.

Layout: ``<results>/<algorithm>/<name>.json``, the case's key (:attr:`~ioc_bench.runner.protocol.Case.key`);
a name is ``<a>__<b>__seed<k>`` with optional ``__model-``, ``__task-``, ``__basis-`` and
``__cfg<hash>`` parts (:data:`RESULT_NAME`), as the tracks' cases name their files (the
synthetic track: ``<weight_set>__<condition>__seed<k>...``, the human track:
``<subject>__<speeds>__seed<k>...``). The config is part of a case's identity in its
canonical form (the fields that differ from the algorithm's defaults,
:func:`~ioc_bench.ioc.registry.canonical_config`): a config that only spells out defaults
names the same file as no config at all.

A file exists only once its case has finished (successfully or not), so a directory of
results is always a consistent record to resume from or to summarise. Readers take only
files named like results (never temporaries, leaderboards or notes that happen to sit
in the folder), and every problem with one is a :class:`ResultFileError` naming the file.

A result file is never trusted: it must be a regular file inside its results folder (no
link leading out, no FIFO or device, at most :data:`MAX_RESULT_BYTES`), a valid record of
the track it names (its :attr:`~ioc_bench.runner.protocol.Track.parse`), and its content
must be the case its name says (the track's ``case_of``: the case's identity fields,
compared through the key they make). One file is one case.
"""

from __future__ import annotations

import contextlib
import os
import re
from collections.abc import Iterator, Mapping, Sequence
from pathlib import Path
from typing import Any

from ioc_bench.fileio import atomic_write_json, remove_temporaries, to_jsonable
from ioc_bench.ioc.registry import NAME_PATTERN
from ioc_bench.paths import PathError, check_input_dir, check_inside, check_path_text, read_bytes
from ioc_bench.processes import hold_across_fork
from ioc_bench.runner.protocol import Case, Record
from ioc_bench.runner.tracks import track_of, track_of_record, tracks
from ioc_bench.validation import load_json, one_line, shown

#: File name of a case result inside its algorithm's folder (condition names may hold a
#: sign, as the robustness suite's ``mass+20``; human cases join speeds and subjects by ``+``).
RESULT_NAME = re.compile(
    r"[A-Za-z0-9._+-]+__[A-Za-z0-9._+-]+__seed[0-9]+(__model-[a-z0-9_-]+)?(__task-[a-z-]+)?(__basis-[a-z0-9-]+)?(__cfg[0-9a-f]{8})?\.json"
)
#: Largest result file read (bytes); a case's record, history included, is some 100 KB.
MAX_RESULT_BYTES = 32 * 2**20


class ResultFileError(ValueError):
    """A result file (or results directory) is missing, unreadable or malformed."""


def write_result(root: str | os.PathLike, spec: Case, result: Record) -> Path:
    """Write ``result`` as the file of ``spec`` under ``root`` (atomically).

    Raises :class:`ResultFileError` if the file would land outside ``root`` (through a
    linked algorithm folder) or cannot be named there; nothing is written then.
    """
    check_case_path(root, spec)
    check_still_held(root)
    data = result.to_dict() | {"case_key": spec.key, "case_config": dict(spec.config)}
    try:
        return atomic_write_json(spec.path(root), data)
    except OSError as exc:  # a full disk, a folder replaced by a file: nothing half-written is left
        raise ResultFileError(f"cannot write the result of {spec.key}: {_one_line(exc)}") from None


def check_case_path(root: str | os.PathLike, spec: Case) -> Path:
    """``spec``'s file under ``root`` if it can be written there and stays inside ``root``.

    Raises :class:`ResultFileError` for a name too long for the file system, an algorithm
    folder that is a file or a link leading out of ``root``.
    """
    path = spec.path(root)
    try:
        check_path_text(path)
        folder = path.parent
        if folder.exists() or folder.is_symlink():
            check_inside(root, folder)  # a link loop, or a link leading out
            if not folder.is_dir():
                raise PathError(f"{folder} is not a directory")
    except PathError as exc:
        raise ResultFileError(f"cannot write the result of {spec.key}: {_one_line(exc)}") from None
    return path


def read_result(path: str | os.PathLike, root: str | os.PathLike | None = None) -> Record:
    """Load one result file; raises :class:`ResultFileError` naming the file and the problem.

    The file must be a regular file (never a link, FIFO or device) of at most
    :data:`MAX_RESULT_BYTES`, and a valid record of the track it names. With ``root``
    (the results folder it lies in) it must also lie inside ``root`` and its content must
    be the case its name says.
    """
    return _read(path, root)[0]


def _read(path: str | os.PathLike, root: str | os.PathLike | None) -> tuple[Record, Case | None]:
    """:func:`read_result`, and with ``root`` the case the file holds."""
    try:
        if root is not None:
            check_inside(root, Path(path).parent)
        raw = read_bytes(path, MAX_RESULT_BYTES, what="result file", follow_symlinks=False)
    except PathError as exc:  # its message names the file
        raise ResultFileError(_one_line(exc)) from None
    try:
        data = load_json(raw.decode("utf-8"))
    except (ValueError, UnicodeDecodeError) as exc:
        raise ResultFileError(f"{path} is not a case result: {_one_line(exc)}") from None
    try:
        result = parse_any(data)
    except ValueError as exc:
        raise ResultFileError(f"{path} is not a case result: {_one_line(exc)}") from None
    if root is None:
        return result, None
    return result, _check_name_matches(Path(path), Path(root), result, data)


def parse_any(data: Any) -> Record:
    """A checked record of whichever track ``data`` names (``ValueError`` naming the problem)."""
    return track_of(data).parse(data)


def _check_name_matches(path: Path, root: Path, result: Record, data: dict) -> Case:
    """The case a file holds; :class:`ResultFileError` if it is another than its name (and place) says."""
    try:
        spec = track_of(data).case_of(result, data.get("case_config"))
    except ValueError as exc:
        raise ResultFileError(f"{path} is not a case result: {_one_line(exc)}") from None
    named = path.relative_to(root).with_suffix("").as_posix() if path.is_relative_to(root) else path.stem
    if spec.key != named:
        raise ResultFileError(f"{path} holds the case {spec.key}, not the one its name says ({named})")
    if data.get("case_key") not in (None, spec.key):
        raise ResultFileError(f"{path} records case_key {shown(data['case_key'])}, but holds the case {spec.key}")
    return spec


def _one_line(exc: BaseException) -> str:
    return one_line(str(exc))


def result_files(root: str | os.PathLike) -> list[Path]:
    """The result files under ``root`` (``<algorithm>/<case>.json``), sorted; nothing else.

    Lists names only (whatever they are: a FIFO or a link named like a result is listed,
    for the reader to refuse by name). Raises :class:`ResultFileError` if ``root`` is not
    a directory.
    """
    root = Path(root)
    if not root.is_dir():
        raise ResultFileError(f"results directory not found: {root}")
    found = []
    for folder in sorted(root.iterdir()):
        if NAME_PATTERN.fullmatch(folder.name) and ".." not in folder.name and folder.is_dir():
            found += [folder / name for name in sorted(os.listdir(folder)) if RESULT_NAME.fullmatch(name)]
    return found


def no_results_message(root: str | os.PathLike) -> str:
    """Why ``root`` holds no results, naming JSON files that are not named like results."""
    listed = set(result_files(root))
    others = sorted(p.relative_to(root).as_posix() for p in _json_files(Path(root)) if p not in listed)
    if not others:
        return f"no case results in {root}"
    shown_files = ", ".join(others[:3]) + (", ..." if len(others) > 3 else "")
    return f"no case results in {root} ({len(others)} .json file(s) not named like results: {shown_files})"


def _json_files(root: Path, limit: int = 1000) -> list[Path]:
    """Up to ``limit`` ``.json`` names under ``root``, never following links to folders."""
    found = []
    for folder, _dirs, names in os.walk(root):
        found += [Path(folder) / n for n in names if n.endswith(".json")]
        if len(found) >= limit:
            break
    return found[:limit]


def load_results(root: str | os.PathLike) -> list[Record]:
    """Every case result under ``root``; any unreadable one, or one that is not the case its
    name says, raises :class:`ResultFileError`."""
    return [read_result(p, root) for p in result_files(root)]


def select_results(root: str | os.PathLike, algorithms: Sequence[str] | None = None) -> list[Record]:
    """The results under the results directory ``root``, restricted to ``algorithms`` (default:
    every one present): what the leaderboard and the figures are made from.

    Raises ``ValueError`` (one line) for a folder that cannot be read
    (:func:`~ioc_bench.paths.check_input_dir`), an unreadable result file
    (:class:`ResultFileError`), no results (saying what the folder holds instead), or a
    requested algorithm that is not in the results (listing those present).
    """
    check_input_dir(root, "results directory")
    results = load_results(root)
    if not results:
        raise ValueError(no_results_message(root))
    return _of_algorithms(results, algorithms)


def _of_algorithms(results: Sequence[Record], algorithms: Sequence[str] | None) -> list[Record]:
    """``results`` of ``algorithms`` (default: all); ``ValueError`` for one that has none."""
    present = sorted({r.algorithm for r in results})
    unknown = [a for a in algorithms or () if a not in present]
    if unknown:
        raise ValueError(f"algorithm(s) not in the results: {', '.join(unknown)}; present: {', '.join(present)}")
    return [r for r in results if not algorithms or r.algorithm in algorithms]


def stored_result(root: str | os.PathLike, spec: Case) -> Record | None:
    """The result stored for ``spec`` under ``root``, or None if there is none yet.

    Raises :class:`ResultFileError` if the case's file cannot be written there (see
    :func:`check_case_path`), or is there but is not a readable result of this very case
    (a file holding another case is never taken as this one done).
    """
    path = check_case_path(root, spec)
    if not (path.exists() or path.is_symlink()):
        return None
    result, recorded = _read(path, root)
    assert recorded is not None  # read with its root
    if type(recorded) is not type(spec):
        raise ResultFileError(f"{path} holds a {recorded.track} case, not the {spec.track} case {spec.key}")
    mine, theirs = identity(spec), identity(recorded)
    differing = [name for name in mine if mine[name] != theirs.get(name)]
    if differing:
        name = differing[0]
        raise ResultFileError(
            f"{path} holds {name} {shown(theirs.get(name))}, not {shown(mine[name])} of the case {spec.key}"
        )
    return result


def identity(spec: Case) -> dict[str, Any]:
    """The fields naming ``spec``, as JSON values (what a record must repeat to be its case's)."""
    names = spec.identity_fields()
    return {name: to_jsonable(dict(v) if isinstance(v := getattr(spec, name), Mapping) else v) for name in names}


@contextlib.contextmanager
def results_directory(root: str | os.PathLike) -> Iterator[Path]:
    """Hold ``root`` for writing: create it, lock it, and remove stale temporaries.

    Only one run may write to a results directory at a time (an advisory lock on the
    folder, released when the process that took it ends, however it ends: forked workers
    never keep it); temporaries left by a killed writer are deleted. Raises
    :class:`ResultFileError` if ``root`` cannot be created or another run holds it.
    """
    root = Path(root)
    try:
        root.mkdir(parents=True, exist_ok=True)
        fd = os.open(root, os.O_RDONLY)
    except OSError as exc:
        raise ResultFileError(f"cannot use {root} as a results directory: {_one_line(exc)}") from None
    try:
        with hold_across_fork(fd):  # a forked worker never keeps the lock
            _lock(fd, root)
            key = _held_key(root)
            _HELD[key] = fd
            try:
                remove_temporaries(root)
                yield root
            finally:
                del _HELD[key]
    finally:
        os.close(fd)


#: The results directories this process holds, by path, with the descriptor that holds each.
_HELD: dict[str, int] = {}


def _held_key(root: Path) -> str:
    return os.path.abspath(root)


def check_still_held(root: str | os.PathLike) -> None:
    """If this process holds ``root`` (:func:`results_directory`), :class:`ResultFileError`
    when the path no longer names the folder it locked (moved away or replaced while the
    run went on): its results must not land in a folder another run may hold."""
    fd = _HELD.get(_held_key(Path(root)))
    if fd is None:
        return
    held = os.fstat(fd)
    try:
        now = os.stat(root)
    except OSError:
        now = None
    if now is None or (now.st_dev, now.st_ino) != (held.st_dev, held.st_ino):
        raise ResultFileError(
            f"{root} is no longer the results folder this run holds (moved or replaced while it ran); "
            "its finished cases are where the folder went"
        )


def check_not_held(root: str | os.PathLike) -> None:
    """Raise :class:`ResultFileError` if another run holds ``root`` (see :func:`results_directory`)."""
    root = Path(root)
    if root.is_dir():
        fd = os.open(root, os.O_RDONLY)
        try:
            _lock(fd, root)  # released with the descriptor
        finally:
            os.close(fd)


def _lock(fd: int, root: Path) -> None:
    try:
        import fcntl
    except ImportError:  # not POSIX: no lock
        return
    try:
        fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
    except BlockingIOError:
        raise ResultFileError(f"another run is writing to {root}; wait for it or use another --out") from None


#: The largest board file read back (``leaderboard.json``).
MAX_BOARD_BYTES = 256 * 2**20


def board_records(path: str | os.PathLike) -> list[Record]:
    """The case records a board keeps in its ``leaderboard.json`` (each track's under its board
    section's ``cases_key``: the synthetic ``cases``, the ``human_cases``), each checked as its
    track reads a kept case (:attr:`~ioc_bench.runner.protocol.BoardSection.parse_kept`: the
    synthetic track's without their per-iteration history, the human track's without their angle
    traces). ``ValueError`` (one line) naming the problem."""
    try:
        data = load_json(read_bytes(path, MAX_BOARD_BYTES, what="board").decode("utf-8"))
    except (ValueError, UnicodeDecodeError) as exc:
        raise ValueError(f"{path} is not a board: {_one_line(exc)}") from None
    keys = [track.board.cases_key for track in tracks() if track.board is not None]
    if not isinstance(data, dict) or not any(isinstance(data.get(key), list) for key in keys):
        raise ValueError(f"{path} is not a board: it has no list of cases (a leaderboard.json holds one)")
    for key in keys:
        if not isinstance(data.get(key, []), list):
            raise ValueError(f"{path} is not a board: its {key} is not a list")
    records: list[Record] = []
    for i, case in enumerate(case for key in keys for case in data.get(key, [])):
        if not isinstance(case, dict):
            raise ValueError(f"{path}: case {i} is not a record")
        try:
            records.append(_parse_kept(case))
        except ValueError as exc:
            raise ValueError(f"{path}: case {i} is not a case result: {_one_line(exc)}") from None
    return records


def _parse_kept(case: dict) -> Record:
    track = track_of(case)
    return track.parse(case) if track.board is None else track.board.parse_kept(case)


def select_sources(sources: Sequence[str | os.PathLike], algorithms: Sequence[str] | None = None) -> list[Record]:
    """The records of several sources, each a results folder (:func:`select_results`) or a
    board's ``leaderboard.json`` (:func:`board_records`): a board regenerated by parts keeps the
    cases it is not given again. A case in more than one source is taken from the last."""
    by_case: dict[tuple[str, str], Record] = {}
    for source in sources:
        records = board_records(source) if Path(source).is_file() else select_results(source)
        for record in records:
            by_case[(track_of_record(record).name, case_key(record))] = record
    return _of_algorithms(list(by_case.values()), algorithms)


def case_key(record: Record) -> str:
    """The key of the case a record holds (as its result file is named)."""
    return track_of_record(record).case_of(record, None).key
