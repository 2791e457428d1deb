"""Result files: one JSON per case, named by the case, written atomically.

Layout: ``<results>/<algorithm>/<weight_set>__<condition>__seed<k>[__model-<model>][__basis-<basis>][__cfg<hash>].json``
(the walker, the default model, and the effort basis, the default basis, are named by no part).
The config is part of a case's identity in its canonical form (the fields that differ
from the algorithm's defaults, :func:`~ioc_bench.ioc.registry.canonical_config`): a
config that only spells out defaults names the same file as no config at all.

A file exists only once its case has finished (successfully or not), so a directory of
results is always a consistent record to resume from or to summarise. Readers take only
files named like results (never temporaries, leaderboards or notes that happen to sit
in the folder), and every problem with one is a :class:`ResultFileError` naming the file.

A result file is never trusted: it must be a regular file inside its results folder (no
link leading out, no FIFO or device, at most :data:`MAX_RESULT_BYTES`), every field typed
and in range (:func:`parse_result`), and its content must be the case its name says
(:func:`recorded_spec`: the case's identity fields, compared through the key they make,
so a field added to :class:`CaseSpec` is compared too). One file is one case.
"""

from __future__ import annotations

import contextlib
import math
import os
import re
from collections.abc import Iterator, Mapping, Sequence
from dataclasses import fields
from pathlib import Path
from typing import Any

import numpy as np

from ioc_bench.bases import DEFAULT_BASIS
from ioc_bench.bench.case import CaseResult, CaseSpec, config_digest
from ioc_bench.bench.protocol import Case, Record, Track
from ioc_bench.checks import check_seed, json_fields, load_json, one_line, shown
from ioc_bench.features import FEATURES
from ioc_bench.fileio import atomic_write_json, remove_temporaries, to_jsonable
from ioc_bench.ioc.algorithm import ModelFit, WeightRegion
from ioc_bench.ioc.contract import MAX_STATUS, check_model_fit, check_region
from ioc_bench.ioc.registry import NAME_PATTERN, check_algorithm_name, config_overrides, make_algorithm
from ioc_bench.paths import PathError, check_input_dir, check_inside, check_path_text, read_bytes
from ioc_bench.processes import hold_across_fork
from ioc_bench.provenance import check_provenance

#: File name of a case result inside its algorithm's folder (condition names may hold a
#: sign, as the robustness suite's ``mass+20``; human cases join speeds and subjects by ``+``).
RESULT_NAME = re.compile(
    r"[A-Za-z0-9._+-]+__[A-Za-z0-9._+-]+__seed[0-9]+(__model-[a-z0-9_-]+)?(__task-[a-z-]+)?(__basis-[a-z0-9-]+)?(__cfg[0-9a-f]{8})?\.json"
)
#: Fields a result file may carry besides :class:`CaseResult`'s (written by :func:`write_result`).
_FILE_FIELDS = {"case_key": str, "case_config": dict[str, Any]}
#: Largest result file read (bytes); a case's record, history included, is some 100 KB.
MAX_RESULT_BYTES = 32 * 2**20
#: Most forward solves a case may record: a day of 1 ms solves is under 10^8.
MAX_SOLVES = 10**9
#: Longest time (seconds) a case may record: some 30 years.
MAX_WALL_TIME = 1e9
#: What a status may look like: the text the plugin contract allows (``converged``,
#: ``failed: <reason>``, at most ``MAX_STATUS`` characters), on one line.
STATUS_PATTERN = re.compile(rf"[^\x00-\x1f\x7f]{{1,{MAX_STATUS}}}")
#: How far a file's true weights may be from its weight set's (unit-norm) truth.
TRUTH_TOLERANCE = 1e-9


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
    """What tables call a result's algorithm: ``name``, then ``(<basis>)`` outside the effort
    basis and ``[cfg <digest>]`` for a non-default config."""
    config = result_config(result)
    label = result.algorithm if result.basis == DEFAULT_BASIS else f"{result.algorithm} ({result.basis})"
    return label if not config else f"{label} [cfg {config_digest(config)}]"


def run_slug(result: CaseResult) -> str:
    """:func:`run_label` for file names: ``name[__basis-<basis>][__cfg<digest>]``."""
    config = result_config(result)
    slug = result.algorithm if result.basis == DEFAULT_BASIS else f"{result.algorithm}__basis-{result.basis}"
    return slug if not config else f"{slug}__cfg{config_digest(config)}"


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
    :data:`MAX_RESULT_BYTES`, and a valid record (:func:`parse_result`). With ``root``
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


def track_of(data: Any) -> Track:
    """The track whose record ``data`` is (by its ``track`` field; none: the synthetic track)."""
    name = data.get("track", "synthetic") if isinstance(data, dict) else "synthetic"
    if name not in TRACKS:
        raise ValueError(f"track must be one of {', '.join(TRACKS)}, got {shown(name)}")
    return TRACKS[name]


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


def recorded_spec(result: CaseResult, case_config: Mapping[str, Any] | None = None) -> CaseSpec:
    """The case a result's content says it is: its values of every :class:`CaseSpec` field.

    Checked as any :class:`CaseSpec` is (``ValueError``). The config is the canonical one:
    the recorded config's fields that differ from the algorithm's defaults, or, where the
    algorithm is not installed here (or has no config dataclass), ``case_config`` as
    :func:`write_result` recorded it. A ``case_config`` that disagrees with the config is
    refused.
    """
    identity = {name: getattr(result, name) for name in case_fields() if name != "config" and hasattr(result, name)}
    spec = CaseSpec(**identity)
    object.__setattr__(spec, "config", _recorded_config(result, case_config))  # already canonical
    return spec


def case_fields() -> tuple[str, ...]:
    """The fields that name a case (:class:`CaseSpec`'s): a file's name and content agree on each."""
    return tuple(f.name for f in fields(CaseSpec) if f.init)


def _recorded_config(result: CaseResult, case_config: Mapping[str, Any] | None) -> dict[str, Any]:
    try:
        defaults = make_algorithm(result.algorithm).config_dict()
    except ValueError:  # the algorithm is not installed here: the file's own record stands
        defaults = {}
    if not defaults:
        return dict(case_config) if case_config is not None else dict(result.config)
    config = config_overrides(result.algorithm, result.config)
    if case_config is not None and to_jsonable(dict(case_config)) != config:
        raise ValueError(
            f"case_config {shown(dict(case_config))} is not its config's difference from the defaults {shown(config)}"
        )
    return config


def parse_result(data: Any, *, history_kept: bool = True) -> CaseResult:
    """A :class:`CaseResult` from a decoded JSON value; ``ValueError`` naming the first problem.

    Checks every field against :class:`CaseResult`'s annotations (numbers are numbers,
    NaN stored as null), that no required field is missing and no unknown one present,
    and that every value is in range (:func:`check_result`). ``history_kept=False`` reads a
    record kept without its per-iteration history (a board's): what derives from the history
    is not checked, and a record that still has one is refused.
    """
    values = json_fields(CaseResult, data, extra=_FILE_FIELDS)
    result = CaseResult(**values)
    if not history_kept and result.history:
        raise ValueError("a case kept without its history has one")
    check_result(result, history_kept=history_kept)
    return result


def check_result(result: CaseResult, *, history_kept: bool = True) -> None:
    """``ValueError`` naming the first value of ``result`` out of its range.

    The identity is a case (algorithm name, model, weight set, condition, seed: the
    :class:`CaseSpec` they make, without config); the features are that case's, known and
    distinct; the true weights are its truth over them; estimated weights non-negative and
    not all zero (or NaN for a failed case); errors and times non-negative (NaN only where
    a case may lack them), a sane solve count, a chosen iteration inside the history, a
    short status, a provenance that is one or ``{}`` (:func:`~ioc_bench.provenance.check_provenance`).
    """
    check_algorithm_name(result.algorithm)
    check_seed(result.seed)
    names = result.features
    if len(set(names)) != len(names) or not set(names) <= set(FEATURES):
        raise ValueError(f"features must be distinct known features, got {shown(list(names))}")
    identity = {f: getattr(result, f) for f in case_fields() if f != "config" and hasattr(result, f)}
    case = CaseSpec(**identity)  # a known model, weight set and condition
    if tuple(names) != tuple(case.features):
        raise ValueError(f"features {list(names)} are not the {case.condition} condition's {list(case.features)}")
    for key in ("weights", "true_weights"):
        if len(getattr(result, key)) != len(names):
            raise ValueError(f"{key} has {len(getattr(result, key))} entries for {len(names)} features")
    expected = case.true_over_features()
    true = np.array(result.true_weights, dtype=float)
    if not np.all(np.isfinite(true)) or np.max(np.abs(true - expected)) > TRUTH_TOLERANCE:
        raise ValueError(
            f"true_weights {shown(list(result.true_weights))} are not the truth of weight set "
            f"{shown(result.weight_set)} over {list(names)}, {shown([round(x, 6) for x in expected.tolist()])}"
        )
    _check_estimate(result)
    _check_numbers(result, history_kept)
    _check_derived(result, history_kept)
    _check_region(result)
    _check_model_fit(result)
    _check_transfer(result)
    check_provenance(result.provenance)
    if not STATUS_PATTERN.fullmatch(result.status):
        raise ValueError(f"status must be one line of 1 to {MAX_STATUS} characters, got {shown(result.status)}")
    unknown = set(result.demo_features) - set(FEATURES)
    if unknown or not all(np.isfinite(v) for v in result.demo_features.values()):
        raise ValueError(f"demo_features must map known features to finite numbers, got {shown(result.demo_features)}")


def _check_estimate(result: CaseResult) -> None:
    w = np.array(result.weights, dtype=float)
    if result.failed:
        if np.any(w[np.isfinite(w)] < 0) or np.any(np.isinf(w)):
            raise ValueError(f"weights must be non-negative or null, got {shown(list(result.weights))}")
        return
    if not np.all(np.isfinite(w)) or np.any(w < 0) or not np.any(w > 0):
        raise ValueError(
            f"weights of a case that did not fail must be finite, non-negative and not all zero, "
            f"got {shown(list(result.weights))}"
        )


#: How far a recorded number may be from what it derives from (float round-trips only).
DERIVED_TOLERANCE = 1e-9


def _check_derived(result: CaseResult, history_kept: bool = True) -> None:
    """Numbers derived from others in the same record agree with them: the estimate has unit
    norm, the weight error is the mean absolute difference to the true weights, the found
    trajectory error is the chosen iteration's, and the forward solves are the oracle's count."""
    if not result.failed:
        w, true = np.array(result.weights, dtype=float), np.array(result.true_weights, dtype=float)
        if abs(np.linalg.norm(w) - 1.0) > 1e-6:
            raise ValueError(f"weights must have unit norm, got norm {np.linalg.norm(w):.6g}")
        expected = float(np.mean(np.abs(w - true)))
        if not abs(result.weight_error - expected) <= DERIVED_TOLERANCE:
            raise ValueError(
                f"weight_error {shown(result.weight_error)} is not the mean |weights - true_weights| of the "
                f"record, {expected:.12g}"
            )
    if history_kept:
        _check_found_error(result)
    calls = result.oracle.get("calls") if isinstance(result.oracle, dict) else None
    if isinstance(calls, dict):
        solves = calls.get("optimize", 0) + calls.get("project", 0)
        if result.oracle.get("forward_solves") != solves or result.n_solves != solves:
            raise ValueError(
                f"n_solves {shown(result.n_solves)} is not the oracle's count of forward solves ({shown(solves)})"
            )


def _check_found_error(result: CaseResult) -> None:
    i, found = result.chosen_iteration, result.found_trajectory_error
    chosen = result.history[i].get("trajectory_error") if i is not None else None
    expected = float(chosen) if _number(chosen) and math.isfinite(chosen) else None
    same = found == expected or (
        found is not None and expected is not None and abs(found - expected) <= DERIVED_TOLERANCE * max(1.0, expected)
    )
    if not same:
        raise ValueError(
            f"found_trajectory_error {shown(found)} is not the chosen iteration's trajectory error {shown(expected)}"
        )


_REGION_KEYS = {"lower", "upper", "level", "covariance", "method"}
_TRANSFER_KEYS = {"speed", "status", "trajectory_error", "excess_cost"}


def _check_region(result: CaseResult) -> None:
    """The region is a valid :class:`WeightRegion` over the case's features, and
    ``covered`` says whether it holds the true weights (None exactly when there is none)."""
    data = result.uncertainty
    if data is None:
        if result.covered is not None:
            raise ValueError(f"covered must be null without an uncertainty region, got {shown(result.covered)}")
        return
    if set(data) != _REGION_KEYS:
        raise ValueError(f"uncertainty must have the fields {sorted(_REGION_KEYS)}, got {shown(sorted(data))}")
    cov = data["covariance"]
    try:
        region = WeightRegion(
            tuple(data["lower"]),
            tuple(data["upper"]),
            data["level"],
            None if cov is None else tuple(map(tuple, cov)),
            data["method"],
        )
    except TypeError:
        raise ValueError("uncertainty.lower, .upper and .covariance must be lists of numbers") from None
    reason = check_region(region, len(result.features))
    if reason:
        raise ValueError(reason)
    holds = region.contains(np.array(result.true_weights, dtype=float))
    if result.covered is not holds:
        raise ValueError(
            f"covered is {shown(result.covered)} but the region {'holds' if holds else 'misses'} the true weights"
        )


_FIT_KEYS = {"rejected", "statistic", "threshold", "noise_level", "tracking_error", "method"}


def _check_model_fit(result: CaseResult) -> None:
    """The misfit test, if any, is a valid :class:`ModelFit` (every field, nothing else)."""
    data = result.model_fit
    if data is None:
        return
    if not isinstance(data, dict) or set(data) != _FIT_KEYS:
        raise ValueError(f"model_fit must have the fields {sorted(_FIT_KEYS)}, got {shown(sorted(data))}")
    reason = check_model_fit(ModelFit(**data))
    if reason:
        raise ValueError(reason)


def _check_transfer(result: CaseResult) -> None:
    """A transfer record has the other speed, a status and (once solved) its two scores."""
    data = result.transfer
    if data is None:
        return
    if (
        not {"speed", "status"} <= set(data) <= _TRANSFER_KEYS
        or len(set(data) & {"trajectory_error", "excess_cost"}) == 1
    ):
        raise ValueError(f"transfer must have speed, status and both scores or neither, got {shown(sorted(data))}")
    speed, status = data["speed"], data["status"]
    if not _number(speed) or not 0 < speed < math.inf:
        raise ValueError(f"transfer.speed must be a positive number, got {shown(speed)}")
    if not isinstance(status, str) or not STATUS_PATTERN.fullmatch(status):
        raise ValueError(f"transfer.status must be one line of 1 to {MAX_STATUS} characters, got {shown(status)}")
    if "trajectory_error" in data:
        error, excess = data["trajectory_error"], data["excess_cost"]
        if error is not None and (not _number(error) or not (math.isnan(error) or 0 <= error < math.inf)):
            raise ValueError(f"transfer.trajectory_error must be a non-negative number or null, got {shown(error)}")
        if excess is not None and (not _number(excess) or math.isinf(excess)):
            raise ValueError(f"transfer.excess_cost must be a finite number or null, got {shown(excess)}")


def _number(value: Any) -> bool:
    return isinstance(value, (int, float)) and not isinstance(value, bool)


def _check_numbers(result: CaseResult, history_kept: bool = True) -> None:
    def check(name: str, value: float | None, upper: float = math.inf, may_be_nan: bool = True) -> None:
        if value is None:
            return
        if math.isnan(value) and may_be_nan:
            return
        if not 0 <= value <= upper:
            what = "a non-negative finite number" if upper == math.inf else f"a number from 0 to {upper:g}"
            raise ValueError(f"{name} must be {what}, got {shown(value)}")

    check("weight_error", result.weight_error, 1.0, may_be_nan=result.failed)
    check("trajectory_error", result.trajectory_error, math.inf)
    check("found_trajectory_error", result.found_trajectory_error, math.inf, may_be_nan=False)
    check("wall_time", result.wall_time, MAX_WALL_TIME, may_be_nan=False)
    check("demo_speed", result.demo_speed, math.inf, may_be_nan=False)
    check("scoring_time", result.scoring_time, MAX_WALL_TIME, may_be_nan=False)
    if not 0 <= result.n_solves <= MAX_SOLVES:
        raise ValueError(f"n_solves must be between 0 and {MAX_SOLVES}, got {shown(result.n_solves)}")
    i = result.chosen_iteration
    if history_kept and i is not None and not 0 <= i < len(result.history):
        raise ValueError(f"chosen_iteration must index the history ({len(result.history)} entries), got {shown(i)}")


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
    names = case_fields() if isinstance(spec, CaseSpec) else spec.identity_fields()
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


def _human_case(record: Any, case_config: Mapping[str, Any] | None) -> Case:
    from ioc_bench.human.case import HumanCaseSpec

    spec = HumanCaseSpec(**{name: getattr(record, name) for name in HumanCaseSpec.identity_fields()})
    if case_config is not None and to_jsonable(dict(case_config)) != to_jsonable(dict(spec.config)):
        raise ValueError(f"case_config {shown(dict(case_config))} is not the record's config {shown(spec.config)}")
    return spec


def _human_parse(data: Any) -> Record:
    from ioc_bench.human.case import parse_record

    return parse_record(data)


#: The tracks whose records a results folder may hold, by the ``track`` their JSON names.
TRACKS: dict[str, Track] = {
    "synthetic": Track("synthetic", parse_result, recorded_spec),
    "human": Track("human", _human_parse, _human_case),
}


#: The largest board file read back (``leaderboard.json``).
MAX_BOARD_BYTES = 256 * 2**20


def board_records(path: str | os.PathLike) -> list[Record]:
    """The case records a board keeps in its ``leaderboard.json`` (its synthetic ``cases`` and
    ``human_cases``), each checked as a result file's. A board keeps a case without its
    per-iteration history (what derives from it is not checked again); human cases keep their
    scores without the angle traces. ``ValueError`` (one line) naming the problem."""
    try:
        data = load_json(read_bytes(path, MAX_BOARD_BYTES, what="board").decode("utf-8"))
    except (ValueError, UnicodeDecodeError) as exc:
        raise ValueError(f"{path} is not a board: {_one_line(exc)}") from None
    if not isinstance(data, dict) or not isinstance(data.get("cases"), list):
        raise ValueError(f"{path} is not a board: it has no list of cases (a leaderboard.json holds one)")
    if not isinstance(data.get("human_cases", []), list):
        raise ValueError(f"{path} is not a board: its human_cases is not a list")
    records: list[Record] = []
    for i, case in enumerate([*data["cases"], *data.get("human_cases", [])]):
        if not isinstance(case, dict):
            raise ValueError(f"{path}: case {i} is not a record")
        kept = {k: v for k, v in case.items() if k != "label"}
        try:
            records.append(parse_any(kept) if "track" in kept else parse_result(kept, history_kept=False))
        except ValueError as exc:
            raise ValueError(f"{path}: case {i} is not a case result: {_one_line(exc)}") from None
    return records


def select_sources(sources: Sequence[str | os.PathLike], algorithms: Sequence[str] | None = None) -> list[Record]:
    """The records of several sources, each a results folder (:func:`select_results`) or a
    board's ``leaderboard.json`` (:func:`board_records`): a board regenerated by parts keeps the
    cases it is not given again. A case in more than one source is taken from the last."""
    by_case: dict[tuple[str, str], Record] = {}
    for source in sources:
        records = board_records(source) if Path(source).is_file() else select_results(source)
        for record in records:
            by_case[(_track_name(record), case_key(record))] = record
    return _of_algorithms(list(by_case.values()), algorithms)


def case_key(record: Record) -> str:
    """The key of the case a record holds (as its result file is named)."""
    return TRACKS[_track_name(record)].case_of(record, None).key


def _track_name(record: Record) -> str:
    return getattr(record, "track", "synthetic")
