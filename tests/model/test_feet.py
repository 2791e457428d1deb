"""Walkers with feet: rolling arcs and ranged joints in the linkage, the parameters and their refusals."""

from __future__ import annotations

import math

import numpy as np
import pytest

from ioc_bench.features import cost_features, model_features
from ioc_bench.model.catalogue import MODELS, get_model, model_of
from ioc_bench.model.feet import (
    ANKLE_FEET,
    ANKLE_RANGE,
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
from ioc_bench.optimize import optimize_gait
from ioc_bench.task import Task
from ioc_bench.weights import parse_weights, weight_sets


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


def test_the_catalogue_holds_the_ankle_feet_walker():
    assert get_model("ankle-feet") is ANKLE_FEET and list(MODELS)[-1] == "ankle-feet"
    params = ANKLE_FEET.default_params
    assert params == footed_params(**REFERENCE_BODY, feet="ankle", knee="free")
    assert params.total_mass == pytest.approx(1.0) and params.leg_length == pytest.approx(1.0)
    assert params.ankle_range == ANKLE_RANGE == (-0.6, 0.6) and params.roll_radius == 0.3
    assert ANKLE_FEET.roles.swap_joints == (
        ("hip_stance", "hip_swing"),
        ("knee_stance", "knee_swing"),
        ("ankle_stance", "ankle_swing"),
    )
    assert ANKLE_FEET.roles.swap_segments[-1] == ("foot_stance", "foot_swing")
    link = ANKLE_FEET.linkage(params)
    assert not link.locked and [j.name for j in link.limited] == [
        "knee_stance", "knee_swing", "ankle_stance", "ankle_swing"
    ]  # fmt: skip


def test_the_model_of_a_walker_with_feet_is_told_by_its_feet():
    assert model_of(FootedParams(feet="ankle")) is ANKLE_FEET and model_of(ANKLE_FEET.default_params) is ANKLE_FEET
    assert (
        model_of(FootedParams()) is ROLLING_FEET
        and model_of(from_walker(WalkerParams(), "roll", "lock")) is ROLLING_FEET
    )
    with pytest.raises(ValueError, match="got FootedParams with feet='point'") as err:
        model_of(FootedParams(feet="point"))
    assert "\n" not in str(err.value) and "FootedParams with feet='ankle' (ankle-feet)" in str(err.value)


def test_the_ankle_feet_walkers_cost_weighs_the_ankles():
    assert cost_features(ANKLE_FEET) == ("hip", "knee", "ankle", "dtau")
    sets = weight_sets(cost_features(ANKLE_FEET))
    assert list(sets) == ["nominal", "penalize-hip", "penalize-knee", "penalize-ankle", "penalize-dtau"]
    w = parse_weights("penalize-ankle", model_features(ANKLE_FEET))
    assert w.argmax() == 2 and w[:4] == pytest.approx(np.array([1, 1, 10, 1]) / np.sqrt(103))
    assert parse_weights("nominal", model_features(ANKLE_FEET))[:4] == pytest.approx(np.full(4, 0.5))
    with pytest.raises(ValueError, match="expected 4 weights"):
        parse_weights("1,10,1", model_features(ANKLE_FEET))


def test_the_ankle_feet_walker_solves_cold(tmp_path):
    """One cold multi-start of the ankle model at a loose setting (10 intervals, no
    local-minimum check) converges, and its demonstration file reads back as ankle-feet."""
    demo = optimize_gait(
        "nominal", task=Task(0.27), starts=3, seed=0, workers=1, n_intervals=10, model=ANKLE_FEET, verify=False
    )
    assert demo.solver.success, demo.solver
    assert demo.model == "ankle-feet" and demo.weights["ankle"] == pytest.approx(0.5)
    assert np.abs(demo.trajectory.tau[:, -2:]).max() > 0  # the ankles work
    again = type(demo).load(demo.save(tmp_path / "ankle.npz"))
    assert again.model == "ankle-feet" and again.params == ANKLE_FEET.default_params
