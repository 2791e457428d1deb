"""Walkers with feet: rolling arcs and ranged joints in the linkage, the parameters and their refusals."""

from __future__ import annotations

import math

import numpy as np
import pytest

from ioc_bench.model.catalogue import get_model, model_of
from ioc_bench.model.feet import (
    REFERENCE_BODY,
    ROLLING_FEET,
    FootedParams,
    FootParams,
    footed_linkage,
    footed_model,
    footed_params,
    from_walker,
)
from ioc_bench.model.linkage import (
    Joint,
    Linkage,
    Pin,
    Segment,
    contact_offset,
    ground_gap,
    ground_gap_rate,
    pin_gap,
    place,
    point_position,
)
from ioc_bench.model.params import WalkerParams


def _wheel(radius: float = 0.3) -> Segment:
    return Segment("wheel", 1.0, 0.1, {"centre": (0.0, 0.0)}, {"centre": radius})


def test_a_rolling_arc_keeps_its_anchor_while_it_rolls():
    """Rolling without slip: the centre moves R per radian, the anchor stays, the height is the arc's bottom."""
    wheel = _wheel()
    for theta in (-0.4, 0.0, 0.7):
        q = (0.3 * theta, 0.3, theta)
        assert ground_gap(wheel, "centre", q) == pytest.approx((0.0, 0.0), abs=1e-15)
    assert ground_gap(wheel, "centre", (0.1, 0.3, 0.0))[0] == pytest.approx(0.1)  # slid: the anchor moved
    assert ground_gap_rate(wheel, "centre", (0, 0.3, 0), (0.3 * 2.0, 0.0, 2.0)) == pytest.approx((0.0, 0.0))
    assert ground_gap_rate(wheel, "centre", (0, 0.3, 0), (0.5, 0.0, 2.0))[0] == pytest.approx(-0.1)


def test_the_ground_force_of_a_rolling_arc_acts_at_its_bottom():
    assert contact_offset(_wheel(0.3), "centre", 0.5) == pytest.approx((0.0, -0.3))
    plain = Segment("s", 1.0, 0.1, {"p": (0.5, 0.0)})
    assert contact_offset(plain, "p", 0.2) == pytest.approx((0.5 * math.sin(0.2), 0.5 * math.cos(0.2)))


def test_place_rolls_the_stance_arc(rng):
    link = footed_linkage(FootedParams())
    q = place(link, rng.normal(0, 0.3, size=len(link.segments)))
    for pin in link.pins:
        assert np.allclose(pin_gap(link, pin, q), 0.0, atol=1e-12)
    shank = link.segment("shank_stance")
    bottom = point_position(shank, "foot", q[link.index("shank_stance")])
    assert bottom[1] == pytest.approx(FootedParams().roll_radius)  # the arc's centre one radius up


def test_arcs_and_ranges_are_checked():
    seg = Segment("a", 1.0, 1.0, {"p": (0.0, 0.0)}, {"q": 0.2})
    with pytest.raises(ValueError, match="rolling arcs at unknown points"):
        Linkage((seg,), (), ())
    a = Segment("a", 1.0, 1.0, {"p": (0.0, 0.0)})
    b = Segment("b", 1.0, 1.0, {"p": (0.0, 0.0)})
    pins = (Pin("j", "b", "p", "a", "p"), Pin("g", "a", "p", None, (0, 0)))
    with pytest.raises(ValueError, match="low < high"):
        Linkage((a, b), pins, (Joint("j", "a", "b", range=(0.5, 0.1)),))
    with pytest.raises(ValueError, match="no lock"):
        Linkage((a, b), pins, (Joint("j", "a", "b", lock=True, range=(0.0, 1.0)),))


def test_parameters_carry_the_arcs():
    link = footed_linkage(FootedParams())
    values = link.parameter_vector()
    assert FootedParams().roll_radius in values
    assert link.with_parameters(values).parameter_vector() == values
    assert link.with_parameters(values).segment("shank_swing").rolls == {"foot": FootedParams().roll_radius}


def test_default_parameters_are_winters_on_the_reference_body():
    p = FootedParams()
    assert p == footed_params(**REFERENCE_BODY)
    assert p.total_mass == pytest.approx(1.0) and p.leg_length == pytest.approx(1.0)
    assert p.thigh.mass == 0.100 and p.shank.mass == pytest.approx(0.0465 + 0.0145)
    ankle = footed_params(**REFERENCE_BODY, feet="ankle")
    assert ankle.total_mass == pytest.approx(1.0) and ankle.leg_length == pytest.approx(1.0)


def test_parameters_round_trip_and_scale():
    p = FootedParams()
    assert FootedParams.from_dict(p.to_dict()) == p
    heavy = p.with_leg_mass_scale(1.1)
    assert heavy.total_mass == pytest.approx(1.0) and heavy.shank.mass == pytest.approx(1.1 * p.shank.mass)


@pytest.mark.parametrize(
    ("make", "match"),
    [
        (lambda: FootedParams(feet="toes"), "feet must be one of"),
        (lambda: FootedParams(knee="stiff"), "knee one of"),
        (lambda: FootedParams(roll_radius=0.0), "roll_radius must be a positive"),
        (lambda: FootedParams(ankle_range=(0.3, -0.3)), "ankle_range"),
        (lambda: FootParams(0.0, 1e-4, 0.08, 0.1, 0.04, 0.05), "foot mass must be positive"),
        (lambda: FootedParams.from_dict({"torso": {}}), "invalid footed-walker parameters"),
        (lambda: footed_params(0.4, 0.4, 0.08, 0.15, 0.5), "must exceed the leg length"),
        (lambda: from_walker(WalkerParams(), "ankle", "free"), "needs footed_params"),
        (lambda: FootedParams().with_leg_mass_scale(10.0), "no mass for the torso"),
    ],
)
def test_bad_parameters_raise_one_line(make, match):
    with pytest.raises(ValueError, match=match) as err:
        make()
    assert "\n" not in str(err.value)


def test_the_kinds_build_their_linkages():
    free = footed_linkage(from_walker(WalkerParams(), "point", "free"))
    assert not free.locked and [j.name for j in free.limited] == ["knee_stance", "knee_swing"]
    locked = footed_linkage(from_walker(WalkerParams(), "point", "lock"))
    assert [j.name for j in locked.locked] == ["knee_stance", "knee_swing"] and not locked.limited
    ankle = footed_model("a", footed_params(**REFERENCE_BODY, feet="ankle"))
    link = ankle.linkage(ankle.default_params)
    assert [j.name for j in link.actuated][-2:] == ["ankle_stance", "ankle_swing"]
    assert ankle.roles.swing_foot == ("foot_swing", "foot") and "ankle" in ankle.actuator_groups


def test_the_catalogue_holds_the_rolling_feet_walker():
    assert get_model("rolling-feet") is ROLLING_FEET and model_of(FootedParams()) is ROLLING_FEET
    assert ROLLING_FEET.roles.swap_joints == (("hip_stance", "hip_swing"), ("knee_stance", "knee_swing"))
