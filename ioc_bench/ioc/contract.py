"""The boundary between an algorithm and the benchmark: everything ``fit`` returns is checked.

:func:`contract_breach` reads an algorithm's answer field by field (the weights, every history
record, the chosen index, the notes, the uncertainty region) and returns a one-line reason
for the first thing that breaks the contract of :mod:`ioc_bench.ioc.algorithm`, or an empty
string. The case pipeline records a case with such a reason as failed, whatever entry point
ran it; nothing downstream (scoring, result files, plots) ever sees an unchecked value.
"""

from __future__ import annotations

import json
import math
import numbers
from collections.abc import Mapping
from typing import Any

import numpy as np

from ioc_bench.ioc.algorithm import IOCResult, IterationRecord, ModelFit, WeightRegion
from ioc_bench.validation import shown
from ioc_bench.weights import weight_fault

#: Longest status text kept (a status is a word or ``failed: <reason>``).
MAX_STATUS = 500
#: Largest ``notes`` or ``extra`` a result may carry, as JSON text.
MAX_NOTES_BYTES = 1_000_000


class ContractError(ValueError):
    """An algorithm returned something the plugin contract does not allow."""


def contract_breach(result: Any, n_features: int) -> str:
    """The first way ``result`` breaks the contract for a problem of ``n_features``, or ``""``
    (a reason, never raised: the case pipeline records it)."""
    try:
        _result(result, n_features)
    except ContractError as exc:
        return str(exc)
    return ""


def _result(result: Any, n: int) -> None:
    if not isinstance(result, IOCResult):
        raise ContractError(f"fit() returned {type(result).__name__}, not IOCResult")
    w = _numbers(result.weights, n, "weights")
    fault = weight_fault(w)
    if fault == "non-finite":
        raise ContractError(f"returned non-finite weights {shown(w.tolist())} (status {shown(result.status)})")
    if fault:
        raise ContractError(f"returned {fault} weights" + ("" if fault == "all-zero" else f" {shown(w.tolist())}"))
    _text(result.status, "status")
    if not isinstance(result.history, (tuple, list)):
        raise ContractError(f"history must be a tuple of IterationRecord, got {type(result.history).__name__}")
    for i, record in enumerate(result.history):
        _record(record, n, f"history[{i}]")
    chosen = result.chosen_iteration
    if chosen is not None and (not _integer(chosen) or not 0 <= chosen < len(result.history)):
        raise ContractError(f"chosen_iteration {shown(chosen)} is not an index into the {len(result.history)} records")
    _json(result.notes, "notes")
    if result.uncertainty is not None:
        _region(result.uncertainty, n)
    if result.model_fit is not None:
        _model_fit(result.model_fit)


def _record(record: Any, n: int, where: str) -> None:
    if not isinstance(record, IterationRecord):
        raise ContractError(f"{where} is a {type(record).__name__}, not an IterationRecord")
    w = _numbers(record.weights, n, f"{where}.weights")
    if not np.all(np.isfinite(w)):
        raise ContractError(f"{where}.weights has non-finite entries")
    for name in ("tracking_error", "trajectory_error"):
        value = getattr(record, name)
        if not _real(value) or (math.isfinite(value) and value < 0):
            raise ContractError(f"{where}.{name} must be a number >= 0 (NaN if unknown), got {shown(value)}")
    _text(record.solve_status, f"{where}.solve_status", empty=True)
    _json(record.extra, f"{where}.extra")


def check_region(region: Any, n_features: int) -> str:
    """The reason ``region`` is not a valid :class:`WeightRegion` over ``n_features``
    weights, or "" if it is (used for a region read back from a result file too)."""
    try:
        _region(region, n_features)
    except ContractError as exc:
        return str(exc)
    return ""


def _region(region: Any, n: int) -> None:
    if not isinstance(region, WeightRegion):
        raise ContractError(f"uncertainty must be a WeightRegion or None, got {type(region).__name__}")
    lower = _numbers(region.lower, n, "uncertainty.lower")
    upper = _numbers(region.upper, n, "uncertainty.upper")
    if not (np.all(np.isfinite(lower)) and np.all(np.isfinite(upper))):
        raise ContractError("uncertainty bounds must be finite")
    if np.any(lower > upper):
        raise ContractError("uncertainty has a lower bound above its upper bound")
    if not (_real(region.level) and 0 < region.level < 1):
        raise ContractError(f"uncertainty.level must be in (0, 1), got {shown(region.level)}")
    if region.covariance is not None:
        try:
            cov = np.asarray(region.covariance, dtype=float)
        except (TypeError, ValueError):
            raise ContractError("uncertainty.covariance must be an F x F matrix of numbers") from None
        if cov.shape != (n, n) or not np.all(np.isfinite(cov)) or not np.allclose(cov, cov.T, atol=1e-12):
            raise ContractError(f"uncertainty.covariance must be a finite symmetric {n} x {n} matrix")
    _text(region.method, "uncertainty.method", empty=True)


def check_model_fit(fit: Any) -> str:
    """The reason ``fit`` is not a valid :class:`ModelFit`, or "" if it is (used for a test
    read back from a result file too)."""
    try:
        _model_fit(fit)
    except ContractError as exc:
        return str(exc)
    return ""


def _model_fit(fit: Any) -> None:
    if not isinstance(fit, ModelFit):
        raise ContractError(f"model_fit must be a ModelFit or None, got {type(fit).__name__}")
    if not isinstance(fit.rejected, (bool, np.bool_)):
        raise ContractError(f"model_fit.rejected must be True or False, got {shown(fit.rejected)}")
    for name in ("statistic", "threshold", "noise_level", "tracking_error"):
        value = getattr(fit, name)
        if not _real(value) or not math.isfinite(value) or value < 0:
            raise ContractError(f"model_fit.{name} must be a finite number >= 0, got {shown(value)}")
    _text(fit.method, "model_fit.method", empty=True)


def _numbers(value: Any, n: int, name: str) -> np.ndarray:
    items = value.tolist() if isinstance(value, np.ndarray) else value
    if isinstance(items, (str, bytes)) or not isinstance(items, (list, tuple)):
        raise ContractError(f"{name} must be a sequence of {n} numbers, got {type(value).__name__}")
    if not all(_real(x) for x in items):
        raise ContractError(f"{name} must hold numbers, got {shown(items)}")
    arr = np.asarray(items, dtype=float)
    if arr.shape != (n,):
        raise ContractError(
            f"returned {arr.size} {name.split('.')[-1]} for {n} features"
            if arr.ndim == 1
            else f"{name} must have shape ({n},), got {arr.shape}"
        )
    return arr


def _real(value: Any) -> bool:
    return isinstance(value, numbers.Real) and not isinstance(value, bool)


def _integer(value: Any) -> bool:
    return isinstance(value, numbers.Integral) and not isinstance(value, bool)


def _text(value: Any, name: str, empty: bool = False) -> None:
    one_line = isinstance(value, str) and value.isprintable()
    if not one_line or (not empty and not value) or len(value) > MAX_STATUS:
        raise ContractError(
            f"{name} must be a{'' if empty else ' non-empty'} text of at most {MAX_STATUS} characters, "
            f"got {shown(value)}"
        )


def _json(value: Any, name: str) -> None:
    if not isinstance(value, Mapping):
        raise ContractError(f"{name} must be a dict, got {type(value).__name__}")
    try:
        text = json.dumps(_plain(value), allow_nan=True)
    except (TypeError, ValueError, RecursionError) as exc:
        raise ContractError(f"{name} must hold JSON values (numbers, text, lists, dicts): {shown(str(exc))}") from None
    if len(text) > MAX_NOTES_BYTES:
        raise ContractError(f"{name} is {len(text)} bytes as JSON, more than {MAX_NOTES_BYTES}")


def _plain(value: Any) -> Any:
    """numpy values as Python ones (the result file's JSON writer converts them alike)."""
    if isinstance(value, Mapping):
        if not all(isinstance(k, str) for k in value):
            raise TypeError("keys must be text")
        return {k: _plain(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_plain(v) for v in value]
    if isinstance(value, (np.ndarray, np.generic)):
        return value.tolist()
    return value
