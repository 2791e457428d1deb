"""The gait models a human step maps to, and the subject's parameters on each.

A person's step is mapped once (:mod:`ioc_bench.human.step`): the four leg segments'
angles, the task, and the subject's walker (Winter's table through
:mod:`ioc_bench.human.anthropometry`). Any model with those four segments under one torso
and a ground pin on the stance shank takes the same angles; the human track's cases run on
such a model end to end (observation, IOC problem, forward solves, cache keys).

- ``walker``: the paper's walker (point feet, knee-lock), the subject's walker itself.
- ``rolling-feet``: the subject's walker's torso, thighs and shanks (knee to floor, the
  foot's mass carried by the shank, as the walker's) with the catalogue model's rolling
  arcs and free knee (:func:`ioc_bench.model.feet.from_walker`): one body, only the foot
  and the knee differ, so a walker and a rolling-feet case of a subject are comparable.

Not mappable: the compass walker (rigid legs: no thigh and shank to take the person's two
leg angles apart) and ``ankle-feet`` (a foot on an ankle: its foot angle is not part of the
mapped step).
"""

from __future__ import annotations

from dataclasses import replace
from typing import Any

from ioc_bench.model.catalogue import MODELS, get_model
from ioc_bench.model.compass import COMPASS
from ioc_bench.model.feet import ANKLE_FEET, ROLLING_FEET, FootedParams, from_walker
from ioc_bench.model.gait_model import GaitModel
from ioc_bench.model.params import WalkerParams
from ioc_bench.model.walker import WALKER

#: The models a human step can be mapped to (the subject's walker is built for them).
HUMAN_MODELS: tuple[str, ...] = (WALKER.name, ROLLING_FEET.name)
#: Why a human step does not map to each of the catalogue's other models.
_NOT_MAPPED: dict[str, str] = {
    COMPASS.name: "a person's step gives a thigh's and a shank's angle per leg",
    ANKLE_FEET.name: "a person's mapped step has no foot angle for its feet on ankles",
}


def check_human_model(name: Any) -> str:
    """``name`` if human steps map to that model; else ``ValueError`` in one line (an
    unknown model, or one of the catalogue without the walker's leg segments)."""
    valid = ", ".join(HUMAN_MODELS)
    if not isinstance(name, str) or name not in MODELS:
        raise ValueError(f"unknown gait model {name!r}; human steps map to the models {valid}")
    if name not in HUMAN_MODELS:
        reason = _NOT_MAPPED.get(name, "its segments are not the walker's")
        raise ValueError(f"human steps map to the models {valid}, not {name!r} ({reason})")
    return name


def human_model(name: str) -> GaitModel:
    """The catalogue's model ``name``, checked by :func:`check_human_model`."""
    return get_model(check_human_model(name))


def subject_params(walker: WalkerParams, model: GaitModel) -> Any:
    """The subject's parameters on ``model``, from the subject's walker ``walker``
    (:attr:`HumanStep.params`): the walker itself, or its segments with the model's foot
    and knee (and foot radius).

    Raises:
        ValueError: a model human steps do not map to.
    """
    defaults = model.default_params
    if isinstance(defaults, WalkerParams):
        return walker
    if isinstance(defaults, FootedParams) and defaults.feet != "ankle":
        return replace(from_walker(walker, defaults.feet, defaults.knee), roll_radius=defaults.roll_radius)
    raise ValueError(f"human steps map to the models {', '.join(HUMAN_MODELS)}, not {model.name!r}")


__all__ = ["HUMAN_MODELS", "check_human_model", "human_model", "subject_params"]
