"""The gait models ioc-bench knows, by name (a demonstration file names its model)."""

from __future__ import annotations

from ioc_bench.model.compass import COMPASS
from ioc_bench.model.feet import ROLLING_FEET
from ioc_bench.model.gait_model import GaitModel
from ioc_bench.model.walker import WALKER

MODELS: dict[str, GaitModel] = {m.name: m for m in (WALKER, COMPASS, ROLLING_FEET)}
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


def model_of(params: object) -> GaitModel:
    """The model whose parameters ``params`` are (by type); ``ValueError`` if none is."""
    for model in MODELS.values():
        if type(params) is type(model.default_params):
            return model
    kinds = ", ".join(f"{type(m.default_params).__name__} ({m.name})" for m in MODELS.values())
    raise ValueError(f"params must be the parameters of a gait model ({kinds}), got {type(params).__name__}")
