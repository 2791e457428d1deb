from __future__ import annotations

import numpy as np
import pytest

from ioc_bench.model.gait_model import permutation
from ioc_bench.model.linkage import Joint, Linkage, Pin, Segment, pin_gap, place, point_position
from ioc_bench.model.walker import WALKER_ROLES, walker_linkage


def test_place_joins_every_pin(rng):
    link = walker_linkage()
    q = place(link, rng.normal(0, 0.3, size=5))
    for pin in link.pins:
        assert np.allclose(pin_gap(link, pin, q), 0.0, atol=1e-12)


def test_segment_axis_convention():
    """theta > 0 leans a segment's top forward (rotation about +y, like MuJoCo)."""
    link = walker_linkage()
    torso = link.segment("torso")
    shoulder = point_position(torso, "shoulder", (0.0, 0.0, 0.1))
    assert shoulder[0] > 0


def test_parameters_round_trip():
    link = walker_linkage()
    values = link.parameter_vector()
    assert link.with_parameters(values).parameter_vector() == values


def test_bad_description_is_refused():
    seg = Segment("a", 1.0, 1.0, {"p": (0.0, 0.0)})
    with pytest.raises(ValueError, match="no point"):
        Linkage((seg,), (Pin("x", "a", "q", None, (0, 0)),), ())
    with pytest.raises(ValueError, match="unknown segment"):
        Linkage((seg,), (), (Joint("j", "a", "b"),))


def test_relabelling_swaps_legs():
    names = ("torso", "thigh_stance", "shank_stance", "thigh_swing", "shank_swing")
    assert permutation(names, WALKER_ROLES.swap_segments) == [0, 3, 4, 1, 2]
