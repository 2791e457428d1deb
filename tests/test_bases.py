"""Cost bases: each basis's features on every model, and names refused with the valid ones."""

from __future__ import annotations

import pytest

from ioc_bench.bases import COST_BASES, DEFAULT_BASIS, get_basis
from ioc_bench.features import FEATURES, cost_features
from ioc_bench.model.catalogue import ANKLE_FEET, COMPASS, ROLLING_FEET
from ioc_bench.model.walker import WALKER


def test_the_default_basis_is_each_models_effort_features() -> None:
    for model in (WALKER, COMPASS, ROLLING_FEET, ANKLE_FEET):
        assert get_basis(DEFAULT_BASIS).features(model) == cost_features(model)


def test_the_energetics_basis_adds_work_and_collision_after_the_efforts() -> None:
    energetics = get_basis("energetics")
    assert energetics.features(WALKER) == ("hip", "knee", "dtau", "work", "collision")
    assert energetics.features(COMPASS) == ("hip", "dtau", "work", "collision")  # no knee to weigh
    assert energetics.features(ANKLE_FEET) == ("hip", "knee", "ankle", "dtau", "work", "collision")
    assert get_basis("effort-work").features(WALKER) == ("hip", "knee", "dtau", "work")


def test_every_basis_names_features_that_exist() -> None:
    assert all(f in FEATURES for basis in COST_BASES.values() for f in basis.extra)


@pytest.mark.parametrize("name", ["rich", "", None, 3])
def test_an_unknown_basis_is_refused_with_the_valid_names(name) -> None:
    with pytest.raises(ValueError, match=r"unknown cost basis .*valid: effort, effort-work, energetics"):
        get_basis(name)


def test_a_basis_reads_its_own_sets_numbers_and_refuses_other_names() -> None:
    energetics = get_basis("energetics")
    work = energetics.parse_weights("penalize-work", WALKER)
    assert work.argmax() == energetics.features(WALKER).index("work")
    efforts_only = energetics.parse_weights("1,10,1", WALKER)  # over the efforts: work and collision 0
    assert efforts_only[3:].tolist() == [0.0, 0.0] and efforts_only.argmax() == 1
    with pytest.raises(ValueError, match=r"unknown weight set 'penalize-ankle'; valid: nominal, .*penalize-collision"):
        energetics.parse_weights("penalize-ankle", WALKER)
