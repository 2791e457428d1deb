"""A synthetic-track record read back: every field typed and in range, and the case it is.

:func:`parse_result` checks a decoded result file as a :class:`CaseResult` (what the runner's
result files and a board's kept cases hold); :func:`recorded_spec` is the case its content
says it is (its identity fields, compared with its file's name by the runner); the labels
(:func:`run_label`, :func:`run_slug`) name a result's algorithm, basis and config in tables
and file names.
"""

from __future__ import annotations

import math
import re
from collections.abc import Mapping
from typing import Any

import numpy as np

from ioc_bench.bases import DEFAULT_BASIS
from ioc_bench.features import FEATURES
from ioc_bench.fileio import to_jsonable
from ioc_bench.ioc.algorithm import ModelFit, WeightRegion
from ioc_bench.ioc.contract import MAX_STATUS, check_model_fit, check_region
from ioc_bench.ioc.registry import check_algorithm_name, config_overrides, make_algorithm
from ioc_bench.provenance import check_provenance
from ioc_bench.synthetic.case import CaseResult, CaseSpec, config_digest
from ioc_bench.validation import check_seed, json_fields, shown

#: Fields a result file may carry besides :class:`CaseResult`'s (the runner's
#: :func:`~ioc_bench.runner.results.write_result` adds them).
_FILE_FIELDS = {"case_key": str, "case_config": dict[str, Any]}
#: Most forward solves a case may record: a day of 1 ms solves is under 10^8.
MAX_SOLVES = 10**9
#: Longest time (seconds) a case may record: some 30 years.
MAX_WALL_TIME = 1e9
#: What a status may look like: the text the plugin contract allows (``converged``,
#: ``failed: <reason>``, at most ``MAX_STATUS`` characters), on one line.
STATUS_PATTERN = re.compile(rf"[^\x00-\x1f\x7f]{{1,{MAX_STATUS}}}")
#: How far a file's true weights may be from its weight set's (unit-norm) truth.
TRUTH_TOLERANCE = 1e-9


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


def recorded_spec(result: CaseResult, case_config: Mapping[str, Any] | None = None) -> CaseSpec:
    """The case a result's content says it is: its values of every :class:`CaseSpec` field.

    Checked as any :class:`CaseSpec` is (``ValueError``). The config is the canonical one:
    the recorded config's fields that differ from the algorithm's defaults, or, where the
    algorithm is not installed here (or has no config dataclass), ``case_config`` as
    :func:`~ioc_bench.runner.results.write_result` recorded it. A ``case_config`` that disagrees with the config is
    refused.
    """
    identity = {name: getattr(result, name) for name in case_fields() if name != "config" and hasattr(result, name)}
    spec = CaseSpec(**identity)
    object.__setattr__(spec, "config", _recorded_config(result, case_config))  # already canonical
    return spec


def case_fields() -> tuple[str, ...]:
    """The fields that name a case (:class:`CaseSpec`'s): a file's name and content agree on each."""
    return CaseSpec.identity_fields()


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


def kept_record(data: Any) -> CaseResult:
    """A record as a board keeps it: without its history, with its row's ``label`` (dropped here)."""
    return parse_result({k: v for k, v in data.items() if k != "label"}, history_kept=False)
