"""The gait models ioc-bench knows, by name (a demonstration file names its model)."""

from __future__ import annotations

from typing import Any

from ioc_bench.model.compass import COMPASS
from ioc_bench.model.feet import ANKLE_FEET, ROLLING_FEET
from ioc_bench.model.gait_model import GaitModel
from ioc_bench.model.walker import WALKER

MODELS: dict[str, GaitModel] = {m.name: m for m in (WALKER, COMPASS, ROLLING_FEET, ANKLE_FEET)}
#: The model meant wherever none is named (a case, a command, a track, the environment): the
#: walker. Named here once; result and cache file names leave it out.
DEFAULT_MODEL: str = WALKER.name


def get_model(name: str) -> GaitModel:
    """The model called ``name``; an unknown name raises ``ValueError`` listing the valid ones."""
    try:
        return MODELS[name]
    except KeyError:
        raise ValueError(f"unknown gait model {name!r}; valid: {', '.join(MODELS)}") from None


def resolve_model(model: str | GaitModel) -> GaitModel:
    """The catalogue's model for a name or a model object (taken by its name): an object that
    is already the catalogue's is kept as is, so a caller that resolved it does not again."""
    if isinstance(model, GaitModel) and MODELS.get(model.name) is model:
        return model
    return get_model(model.name if isinstance(model, GaitModel) else model)


def params_kind(params: object) -> tuple[type, Any]:
    """What tells the catalogue's models apart by their parameters: the parameters' type and
    their feet's kind, if they have feet (``rolling-feet`` and ``ankle-feet`` share a type)."""
    return type(params), getattr(params, "feet", None)


def _describe(kind: tuple[type, Any]) -> str:
    cls, feet = kind
    return cls.__name__ if feet is None else f"{cls.__name__} with feet={feet!r}"


def _by_kind(models: dict[str, GaitModel]) -> dict[tuple[type, Any], GaitModel]:
    """Each model by the kind of its default parameters; two models of one kind are refused
    (:func:`model_of` could not tell them apart)."""
    table: dict[tuple[type, Any], GaitModel] = {}
    for model in models.values():
        kind = params_kind(model.default_params)
        if kind in table:
            raise ValueError(f"models {table[kind].name!r} and {model.name!r} share parameters {_describe(kind)}")
        table[kind] = model
    return table


def model_of(params: object) -> GaitModel:
    """The model whose parameters ``params`` are (by :func:`params_kind`); ``ValueError`` if none is."""
    table, kind = _by_kind(MODELS), params_kind(params)
    if kind not in table:
        kinds = ", ".join(f"{_describe(k)} ({m.name})" for k, m in table.items())
        raise ValueError(f"params must be the parameters of a gait model ({kinds}), got {_describe(kind)}")
    return table[kind]
