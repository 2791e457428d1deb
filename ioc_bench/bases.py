"""Cost bases: the features a cost's weights range over, declared by name.

A basis is a model's effort features (its torque efforts and the torque rate: the paper's
cost, :func:`~ioc_bench.features.cost_features`) and, by name, further features of
:data:`~ioc_bench.features.FEATURES` that lie outside the benchmark's default basis. Every
model has every basis, restricted to the features it has (a model without ankles weighs no
ankle effort). What a basis holds and why is in ``docs/spec.md`` ("Cost bases").
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from ioc_bench.features import available_features, cost_features, model_features
from ioc_bench.model.gait_model import GaitModel
from ioc_bench.weights import WeightSpec, names_a_set, normalize, parse_weights, weight_sets


@dataclass(frozen=True)
class CostBasis:
    """A named cost basis: the model's effort features, then :attr:`extra` (those it has)."""

    name: str
    description: str
    extra: tuple[str, ...] = ()

    def features(self, model: GaitModel) -> tuple[str, ...]:
        """The basis's features on ``model``, in weight order."""
        own = available_features(model)
        return (*cost_features(model), *(f for f in self.extra if f in own))

    def weight_sets(self, model: GaitModel) -> dict[str, tuple[float, ...]]:
        """The named weight sets over the basis's features on ``model`` (``nominal`` and one
        ``penalize-<feature>`` each, :func:`~ioc_bench.weights.weight_sets`)."""
        return weight_sets(self.features(model))

    def parse_weights(self, spec: WeightSpec, model: GaitModel) -> np.ndarray:
        """Unit weights over the basis's features on ``model`` from one of its set names or
        anything :func:`~ioc_bench.weights.parse_weights` reads (numbers over the model's
        effort features leave the others at 0)."""
        return parse_basis_weights(spec, self.features(model))


def parse_basis_weights(spec: WeightSpec, features: Sequence[str]) -> np.ndarray:
    """Unit weights over a basis's ``features`` (:meth:`CostBasis.features`, computed once by
    the caller) from one of its set names or anything :func:`~ioc_bench.weights.parse_weights` reads."""
    sets = weight_sets(features)
    if isinstance(spec, str) and names_a_set(spec):
        if spec not in sets:
            raise ValueError(f"unknown weight set {spec!r}; valid: {', '.join(sets)}")
        return normalize(sets[spec])
    return parse_weights(spec, features)


#: The basis every track uses unless told otherwise: the paper's effort features.
DEFAULT_BASIS = "effort"

COST_BASES: dict[str, CostBasis] = {
    b.name: b
    for b in (
        CostBasis(DEFAULT_BASIS, "the model's torque efforts and torque rate (the paper's cost)"),
        CostBasis("effort-work", "the efforts and the positive work of the joints", ("work",)),
        CostBasis(
            "energetics",
            "the efforts, the positive work of the joints and the energy heel strike removes",
            ("work", "collision"),
        ),
    )
}


def get_basis(name: str) -> CostBasis:
    """The basis named ``name`` (``ValueError`` listing the valid names otherwise)."""
    if not isinstance(name, str) or name not in COST_BASES:
        raise ValueError(f"unknown cost basis {name!r}; valid: {', '.join(COST_BASES)}")
    return COST_BASES[name]


def forward_basis(model: GaitModel, features: Sequence[str]) -> tuple[str, ...] | None:
    """The basis of the forward problem an IOC over ``features`` solves: the model's default
    basis (None), with the features outside it that ``features`` names, in
    :func:`~ioc_bench.features.available_features` order."""
    extra = [f for f in available_features(model) if f in features and f not in model_features(model)]
    return (*model_features(model), *extra) if extra else None
