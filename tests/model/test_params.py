from __future__ import annotations

import math

import pytest

from ioc_bench import SegmentParams, WalkerParams


def test_defaults_are_the_spec_walker():
    p = WalkerParams()
    assert p.total_mass == pytest.approx(1.0)
    assert p.leg_length == pytest.approx(1.0)
    assert (p.torso.mass, p.thigh.mass, p.shank.mass) == (0.678, 0.100, 0.061)
    assert (p.torso.inertia, p.thigh.inertia, p.shank.inertia) == (0.050, 0.0022, 0.0016)


def test_leg_mass_variant_keeps_total_mass():
    heavy = WalkerParams().with_leg_mass_scale(1.1)
    assert heavy.total_mass == pytest.approx(1.0)
    assert heavy.thigh.mass == pytest.approx(0.110) and heavy.shank.mass == pytest.approx(0.0671)
    assert heavy.torso.mass == pytest.approx(0.678 - 0.0322)


def test_round_trip_and_validation():
    p = WalkerParams().with_leg_mass_scale(1.1)
    assert WalkerParams.from_dict(p.to_dict()) == p
    with pytest.raises(ValueError, match="mass"):
        SegmentParams(0.5, -1.0, 0.2, 0.01)
    with pytest.raises(ValueError, match="friction"):
        WalkerParams(friction=math.nan)
    with pytest.raises(ValueError, match="invalid walker parameters"):
        WalkerParams.from_dict({"torso": {}})
