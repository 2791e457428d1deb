"""Cost weights: the named sets of SPEC section 2 and the parsing every entry point shares."""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np

from ioc_bench.features import ALL_FEATURES, COST_FEATURES

#: The paper's four weight sets over (hip, knee, dtau), before normalisation.
WEIGHT_SETS: dict[str, tuple[float, float, float]] = {
    "nominal": (1.0, 1.0, 1.0),
    "penalize-hip": (10.0, 1.0, 1.0),
    "penalize-knee": (1.0, 10.0, 1.0),
    "penalize-dtau": (1.0, 1.0, 10.0),
}

WeightSpec = str | Sequence[float] | Mapping[str, float] | np.ndarray


def normalize(values: Sequence[float]) -> np.ndarray:
    """Validate weights and scale them to unit 2-norm."""
    arr = _numbers(values)
    if not np.all(np.isfinite(arr)):
        raise ValueError(f"weights must be finite numbers, got {arr.tolist()}")
    if np.any(arr < 0):
        raise ValueError(f"weights must be non-negative, got {arr.tolist()}")
    if not np.any(arr > 0):
        raise ValueError("weights must not all be zero")
    with np.errstate(over="ignore", under="ignore"):
        norm = float(np.linalg.norm(arr))
    if not np.isfinite(norm) or norm < np.finfo(float).tiny:  # huge or subnormal: scale first
        arr = arr / arr.max()
        norm = float(np.linalg.norm(arr))
    return arr / norm


def _numbers(values: object) -> np.ndarray:
    """``values`` as a flat float array; ``ValueError`` for anything but numbers (bools included)."""
    items = values.tolist() if isinstance(values, np.ndarray) else values
    if not isinstance(items, (list, tuple)):
        items = [items]
    if any(v is None or isinstance(v, (bool, np.bool_)) for v in items):
        raise ValueError(f"weights must be numbers, got {values!r}")
    try:
        return np.asarray(values, dtype=float).ravel()
    except (TypeError, ValueError):
        raise ValueError(f"weights must be numbers, got {values!r}") from None


def parse_weights(spec: WeightSpec, features: Sequence[str] = COST_FEATURES) -> np.ndarray:
    """Unit-norm weights over ``features`` from a set name, numbers, or a name->value map.

    Accepts a name of :data:`WEIGHT_SETS`, comma-separated numbers (``"1,10,1"``), a
    sequence of numbers (one per feature), or a mapping from feature name to weight
    (missing features get 0). Raises ``ValueError`` with a one-line reason otherwise.
    """
    if isinstance(spec, str):
        if spec in WEIGHT_SETS:
            values: Sequence[float] = WEIGHT_SETS[spec]
        elif "," in spec or _is_number(spec):
            try:
                values = [float(s) for s in spec.split(",")]
            except ValueError:
                raise ValueError(f"cannot read weights {spec!r}: expected numbers like 1,10,1") from None
        else:
            raise ValueError(f"unknown weight set {spec!r}; valid: {', '.join(WEIGHT_SETS)}")
    elif isinstance(spec, Mapping):
        unknown = [k for k in spec if k not in features]
        if unknown:
            raise ValueError(f"weights name unknown feature(s) {unknown}; valid: {', '.join(features)}")
        values = list(_numbers([spec.get(f, 0.0) for f in features]))
    else:
        values = list(_numbers(spec))
    if len(values) == len(COST_FEATURES) and len(features) > len(COST_FEATURES):
        values = list(values) + [0.0] * (len(features) - len(COST_FEATURES))
    if len(values) != len(features):
        counts = f"{len(COST_FEATURES)} weights ({', '.join(COST_FEATURES)})"
        if len(features) != len(COST_FEATURES):
            counts += f" or {len(features)} ({', '.join(features)})"
        raise ValueError(f"expected {counts}, got {len(values)}")
    return normalize(values)


def full_weights(weights: np.ndarray, features: Sequence[str], into: Sequence[str] = ALL_FEATURES) -> np.ndarray:
    """Weights over ``features`` placed into a vector over ``into`` (others 0)."""
    out = np.zeros(len(into))
    for w, f in zip(weights, features):
        out[list(into).index(f)] = w
    return out


def _is_number(text: str) -> bool:
    try:
        float(text)
    except ValueError:
        return False
    return True
