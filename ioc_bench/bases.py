"""Cost bases: the features a cost's weights range over, declared by name.

A basis is a model's effort features (its torque efforts and the torque rate: the paper's
cost, :func:`~ioc_bench.features.cost_features`) and, by name, further features of
:data:`~ioc_bench.features.FEATURES` that lie outside the benchmark's default basis. Every
model has every basis, restricted to the features it has (a model without ankles weighs no
ankle effort). What a basis holds and why is in ``docs/spec.md`` ("Cost bases").
"""

from __future__ import annotations

from dataclasses import dataclass

from ioc_bench.features import available_features, cost_features
from ioc_bench.model.gait_model import GaitModel


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


#: The basis every track uses unless told otherwise: the paper's effort features.
DEFAULT_BASIS = "effort"

COST_BASES: dict[str, CostBasis] = {
    b.name: b
    for b in (
        CostBasis(DEFAULT_BASIS, "the model's torque efforts and torque rate (the paper's cost)"),
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
