"""Cost weights: the named sets (``docs/spec.md``, "Weight sets") and the parsing every entry point shares."""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np

from ioc_bench.features import ALL_FEATURES, COST_FEATURES, efforts

#: The factor a ``penalize-<feature>`` set puts on its feature (the others 1).
PENALTY = 10.0
#: The name of the set that penalises a feature is this prefix and the feature's name.
PENALIZE_PREFIX = "penalize-"


def weight_sets(cost: Sequence[str] = COST_FEATURES) -> dict[str, tuple[float, ...]]:
    """The named weight sets over a model's cost features: ``nominal`` (all ones) and one
    ``penalize-<feature>`` each (10 on it, 1 elsewhere); the paper's four for the walker."""
    sets = {"nominal": tuple(1.0 for _ in cost)}
    for f in cost:
        sets[PENALIZE_PREFIX + f] = tuple(PENALTY if g == f else 1.0 for g in cost)
    return sets


def penalised_feature(name: str, features: Sequence[str] = COST_FEATURES) -> str | None:
    """The feature of ``features`` that the weight set ``name`` penalises (``penalize-<feature>``
    of :func:`weight_sets`), or None if the set penalises none of them."""
    return next((f for f in features if name == PENALIZE_PREFIX + f), None)


#: The paper's four weight sets over the walker's (hip, knee, dtau), before normalisation.
WEIGHT_SETS: dict[str, tuple[float, ...]] = weight_sets(COST_FEATURES)


WeightSpec = str | Sequence[float] | Mapping[str, float] | np.ndarray


def weight_fault(weights: np.ndarray) -> str:
    """What makes numbers no weight vector: ``"non-finite"``, ``"negative"`` or ``"all-zero"``
    (the first that applies), or ``""`` for valid weights."""
    if not np.all(np.isfinite(weights)):
        return "non-finite"
    if np.any(weights < 0):
        return "negative"
    if not np.any(weights > 0):
        return "all-zero"
    return ""


_FAULT_MESSAGES = {
    "non-finite": "weights must be finite numbers, got {}",
    "negative": "weights must be non-negative, got {}",
    "all-zero": "weights must not all be zero",
}


def normalize(values: Sequence[float]) -> np.ndarray:
    """Validate weights (:func:`weight_fault`) and scale them to unit 2-norm."""
    arr = _numbers(values)
    fault = weight_fault(arr)
    if fault:
        raise ValueError(_FAULT_MESSAGES[fault].format(arr.tolist()))
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

    Accepts a name of :func:`weight_sets` for the effort features among ``features`` (for
    the walker: :data:`WEIGHT_SETS`; with an ankle: ``penalize-ankle`` too), comma-separated
    numbers (``"1,10,1"``), a sequence of numbers (one per effort feature, or one per
    feature), or a mapping from feature name to weight (missing features get 0). Raises
    ``ValueError`` with a one-line reason otherwise.
    """
    cost = efforts(features)
    sets = weight_sets(cost)
    if isinstance(spec, str):
        if spec in sets:
            values: Sequence[float] = sets[spec]
        elif not names_a_set(spec):
            try:
                values = [float(s) for s in spec.split(",")]
            except ValueError:
                raise ValueError(f"cannot read weights {spec!r}: expected numbers like 1,10,1") from None
        else:
            raise ValueError(f"unknown weight set {spec!r}; valid: {', '.join(sets)}")
    elif isinstance(spec, Mapping):
        unknown = [k for k in spec if k not in features]
        if unknown:
            raise ValueError(f"weights name unknown feature(s) {unknown}; valid: {', '.join(features)}")
        values = list(_numbers([spec.get(f, 0.0) for f in features]))
    else:
        values = list(_numbers(spec))
    if len(values) == len(cost) and len(features) > len(cost):  # over the cost features: others 0
        given = dict(zip(cost, values))
        values = [given.get(f, 0.0) for f in features]
    if len(values) != len(features):
        counts = f"{len(cost)} weights ({', '.join(cost)})"
        if len(features) != len(cost):
            counts += f" or {len(features)} ({', '.join(features)})"
        raise ValueError(f"expected {counts}, got {len(values)}")
    return normalize(values)


def full_weights(weights: np.ndarray, features: Sequence[str], into: Sequence[str] = ALL_FEATURES) -> np.ndarray:
    """Weights over ``features`` placed into a vector over ``into`` (others 0)."""
    out = np.zeros(len(into))
    for w, f in zip(weights, features):
        out[list(into).index(f)] = w
    return out


def names_a_set(spec: str) -> bool:
    """Whether a weight spec given as text is read as a set's name (not as numbers)."""
    if "," in spec:
        return False
    try:
        float(spec)
    except ValueError:
        return True
    return False


def simplex_weight_sets(n: int, seed: int, n_features: int = len(COST_FEATURES)) -> tuple[str, ...]:
    """``n`` weight sets drawn uniformly from the simplex (Dirichlet(1, ..., 1), seeded), each
    written as comma-separated numbers to 3 decimals (a name no algorithm can be tuned to)."""
    draws = np.random.default_rng(seed).dirichlet(np.ones(n_features), size=n)
    return tuple(",".join(f"{x:.3f}" for x in w) for w in draws)
