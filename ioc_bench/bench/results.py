"""Result files: one JSON per case, named by the case, written atomically.

Layout: ``<results>/<algorithm>/<weight_set>__<condition>__seed<k>[__model-<model>][__cfg<hash>].json``
(the walker's cases name no model: their files are as before models).
The config is part of a case's identity in its canonical form (the fields that differ
from the algorithm's defaults, :func:`~ioc_bench.ioc.registry.canonical_config`): a
config that only spells out defaults names the same file as no config at all.

A file exists only once its case has finished (successfully or not), so a directory of
results is always a consistent record to resume from or to summarise. Readers take only
files named like results (never temporaries, leaderboards or notes that happen to sit
in the folder), and every problem with one is a :class:`ResultFileError` naming the file.
"""

from __future__ import annotations

import contextlib
import json
import os
import re
import typing
from collections.abc import Iterator
from dataclasses import MISSING, fields
from pathlib import Path
from typing import Any

from ioc_bench.bench.case import CaseResult, CaseSpec, config_digest
from ioc_bench.checks import TypeMismatch, coerce
from ioc_bench.fileio import atomic_write_json, remove_temporaries
from ioc_bench.ioc.registry import NAME_PATTERN, config_overrides

#: File name of a case result inside its algorithm's folder (condition names may hold a
#: sign, as the robustness suite's ``mass+20``).
RESULT_NAME = re.compile(
    r"[A-Za-z0-9._-]+__[A-Za-z0-9._+-]+__seed[0-9]+(__model-[a-z0-9_-]+)?(__cfg[0-9a-f]{8})?\.json"
)
#: Fields a result file may carry besides :class:`CaseResult`'s (written by :func:`write_result`).
_FILE_FIELDS = {"case_key": str, "case_config": dict[str, Any]}


class ResultFileError(ValueError):
    """A result file (or results directory) is missing, unreadable or malformed."""


def result_config(result: CaseResult) -> dict[str, Any]:
    """The canonical config a result was made with: its fields that differ from the defaults.

    Needs the algorithm to be available to know its defaults; if it is not, the whole
    recorded config stands for itself (still never equal to another config's).
    """
    if not result.config:
        return {}
    try:
        return config_overrides(result.algorithm, result.config)
    except ValueError:  # the algorithm is not installed here
        return dict(result.config)


def run_label(result: CaseResult) -> str:
    """What tables call a result's algorithm: ``name``, or ``name [cfg <digest>]`` for a non-default config."""
    config = result_config(result)
    return result.algorithm if not config else f"{result.algorithm} [cfg {config_digest(config)}]"


def run_slug(result: CaseResult) -> str:
    """:func:`run_label` for file names: ``name`` or ``name__cfg<digest>``."""
    config = result_config(result)
    return result.algorithm if not config else f"{result.algorithm}__cfg{config_digest(config)}"


def write_result(root: str | os.PathLike, spec: CaseSpec, result: CaseResult) -> Path:
    """Write ``result`` as the file of ``spec`` under ``root`` (atomically)."""
    data = result.to_dict() | {"case_key": spec.key, "case_config": dict(spec.config)}
    return atomic_write_json(spec.path(root), data)


def read_result(path: str | os.PathLike) -> CaseResult:
    """Load one result file; raises :class:`ResultFileError` naming the file and the problem."""
    try:
        text = Path(path).read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as exc:
        raise ResultFileError(f"cannot read result file {path}: {_one_line(exc)}") from None
    try:
        data = json.loads(text)
    except ValueError as exc:
        raise ResultFileError(f"{path} is not a case result: not JSON ({_one_line(exc)})") from None
    try:
        return parse_result(data)
    except ValueError as exc:
        raise ResultFileError(f"{path} is not a case result: {_one_line(exc)}") from None


def parse_result(data: Any) -> CaseResult:
    """A :class:`CaseResult` from a decoded JSON value; ``ValueError`` naming the first problem.

    Checks every field against :class:`CaseResult`'s annotations (numbers are numbers,
    NaN stored as null), that no required field is missing and no unknown one present, and
    that the weight vectors have one entry per feature.
    """
    if not isinstance(data, dict):
        raise ValueError(f"expected a JSON object, got {_json_kind(data)}")
    hints = typing.get_type_hints(CaseResult)
    required = [f.name for f in fields(CaseResult) if f.default is MISSING and f.default_factory is MISSING]
    missing = [k for k in required if k not in data]
    if missing:
        raise ValueError(f"missing field(s) {', '.join(missing)}")
    unknown = [k for k in data if k not in hints and k not in _FILE_FIELDS]
    if unknown:
        raise ValueError(f"unknown field(s) {', '.join(map(str, unknown))}")
    values = {}
    for key, value in data.items():
        try:
            checked = coerce(value, hints.get(key) or _FILE_FIELDS[key], nonfinite=True)
        except TypeMismatch as exc:
            raise ValueError(f"{key} must be {exc}, got {_json_kind(value)}") from None
        if key in hints:
            values[key] = checked
    result = CaseResult(**values)
    n = len(result.features)
    for key in ("weights", "true_weights"):
        if len(getattr(result, key)) != n:
            raise ValueError(f"{key} has {len(getattr(result, key))} entries for {n} features")
    if result.seed < 0:
        raise ValueError(f"seed must be >= 0, got {result.seed}")
    return result


def _json_kind(value: Any) -> str:
    if value is None:
        return "null"
    text = json.dumps(value) if isinstance(value, (bool, int, float, str)) else type(value).__name__
    return text if len(text) <= 40 else text[:37] + "..."


def _one_line(exc: BaseException) -> str:
    return " ".join(str(exc).split())


def result_files(root: str | os.PathLike) -> list[Path]:
    """The result files under ``root`` (``<algorithm>/<case>.json``), sorted; nothing else.

    Raises :class:`ResultFileError` if ``root`` is not a directory.
    """
    root = Path(root)
    if not root.is_dir():
        raise ResultFileError(f"results directory not found: {root}")
    return sorted(
        p for p in root.glob("*/*.json") if RESULT_NAME.fullmatch(p.name) and NAME_PATTERN.fullmatch(p.parent.name)
    )


def no_results_message(root: str | os.PathLike) -> str:
    """Why ``root`` holds no results, naming JSON files that are not named like results."""
    others = sorted(p.relative_to(root).as_posix() for p in Path(root).rglob("*.json") if p not in result_files(root))
    if not others:
        return f"no case results in {root}"
    shown = ", ".join(others[:3]) + (", ..." if len(others) > 3 else "")
    return f"no case results in {root} ({len(others)} .json file(s) not named like results: {shown})"


def load_results(root: str | os.PathLike) -> list[CaseResult]:
    """Every case result under ``root``; any unreadable one raises :class:`ResultFileError`."""
    return [read_result(p) for p in result_files(root)]


def stored_result(root: str | os.PathLike, spec: CaseSpec) -> CaseResult | None:
    """The result stored for ``spec`` under ``root``, or None if there is none yet.

    Raises :class:`ResultFileError` if a file is there but is not a readable result.
    """
    path = spec.path(root)
    if not path.exists():
        return None
    return read_result(path)


@contextlib.contextmanager
def results_directory(root: str | os.PathLike) -> Iterator[Path]:
    """Hold ``root`` for writing: create it, lock it, and remove stale temporaries.

    Only one run may write to a results directory at a time (an advisory lock on the
    folder, released when the process ends, however it ends); temporaries left by a
    killed writer are deleted. Raises :class:`ResultFileError` if ``root`` cannot be
    created or another run holds it.
    """
    root = Path(root)
    try:
        root.mkdir(parents=True, exist_ok=True)
        fd = os.open(root, os.O_RDONLY)
    except OSError as exc:
        raise ResultFileError(f"cannot use {root} as a results directory: {_one_line(exc)}") from None
    try:
        _lock(fd, root)
        remove_temporaries(root)
        yield root
    finally:
        os.close(fd)


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
