"""The MJCF is generated from the model's parameters and matches the optimizer's walker
(point feet) or walker with rolling feet."""

from __future__ import annotations

from dataclasses import replace

import mujoco
import numpy as np
import pytest

from ioc_bench import WalkerParams
from ioc_bench.model.feet import ANKLE_FEET, ROLL_RADIUS, FootedParams, footed_linkage
from ioc_bench.model.mjcf import (
    FOOT_RADIUS,
    JOINTS,
    MJCF_MODELS,
    MOTORS,
    ContactSettings,
    FootSphere,
    check_mjcf_model,
    foot_sphere,
    model_mjcf,
    rolling_feet_mjcf,
    walker_mjcf,
)
from ioc_bench.model.params import CompassParams
from ioc_bench.model.walker import ACTUATORS


def _model(params: WalkerParams | None = None) -> mujoco.MjModel:
    return mujoco.MjModel.from_xml_string(walker_mjcf(params))


def _names(model: mujoco.MjModel, kind: str, count: int) -> list[str]:
    return [getattr(model, kind)(i).name for i in range(count)]


def test_layout_joints_and_motors_share_names():
    m = _model()
    assert (m.nq, m.nv, m.nu) == (7, 7, 4)
    assert tuple(_names(m, "joint", m.njnt)) == JOINTS
    assert tuple(_names(m, "actuator", m.nu)) == MOTORS
    assert set(MOTORS) <= set(JOINTS)
    # Motors follow ACTUATORS with leg a in the stance role.
    assert [n.replace("_a", "_stance").replace("_b", "_swing") for n in MOTORS] == list(ACTUATORS)
    for i in range(m.nu):
        assert m.joint(int(m.actuator_trnid[i, 0])).name == m.actuator(i).name


def test_every_element_is_named():
    m = _model()
    for kind, count in (("body", m.nbody), ("geom", m.ngeom), ("site", m.nsite), ("camera", m.ncam)):
        names = _names(m, kind, count)
        assert kind == "body" or all(names), f"unnamed {kind}"
        assert len(set(names)) == len(names)
    assert all(_names(m, "body", m.nbody)[1:])  # body 0 is MuJoCo's world


@pytest.mark.parametrize("params", [WalkerParams(), WalkerParams().with_leg_mass_scale(1.1)], ids=["nominal", "heavy"])
def test_inertial_properties_come_from_params(params: WalkerParams):
    m = _model(params)
    for leg in "ab":
        for body, seg, sign in (("thigh", params.thigh, -1), ("shank", params.shank, -1)):
            b = m.body(f"{body}_{leg}")
            assert b.mass[0] == pytest.approx(seg.mass)
            assert b.inertia[1] == pytest.approx(seg.inertia)  # about y: the parameters' value
            assert b.ipos == pytest.approx([0, 0, sign * seg.com])
            # MuJoCo's triangle inequality holds with small off-plane inertia.
            assert b.inertia[2] < 0.01 * seg.inertia
    torso = m.body("torso")
    assert torso.mass[0] == pytest.approx(params.torso.mass)
    assert torso.inertia[1] == pytest.approx(params.torso.inertia)
    assert torso.ipos == pytest.approx([0, 0, params.torso.com])
    assert m.body_mass.sum() == pytest.approx(params.total_mass)


def test_heavy_variant_needs_no_code():
    nominal, heavy = _model(), _model(WalkerParams().with_leg_mass_scale(1.1))
    assert heavy.body("thigh_a").mass[0] == pytest.approx(1.1 * nominal.body("thigh_a").mass[0])
    assert heavy.body("torso").mass[0] < nominal.body("torso").mass[0]
    assert heavy.body_mass.sum() == pytest.approx(1.0)


def test_limits_friction_gravity_and_torque_bounds():
    params = WalkerParams(friction=0.7, max_torque=0.5, knee_max_flexion=2.0, gravity=1.0)
    m = _model(params)
    for leg in "ab":
        assert m.joint(f"knee_{leg}").range == pytest.approx([0.0, 2.0])
        assert m.jnt_limited[m.joint(f"knee_{leg}").id]
        assert not m.jnt_limited[m.joint(f"hip_{leg}").id]
        assert m.geom(f"foot_{leg}").friction[0] == pytest.approx(0.7)
    assert m.geom("floor").friction[0] == pytest.approx(0.7)
    assert m.opt.gravity == pytest.approx([0, 0, -1.0])
    assert np.allclose(m.actuator_ctrlrange, [[-0.5, 0.5]] * 4)
    assert np.all(m.actuator_ctrllimited)


def test_foot_point_touches_floor_at_zero_height():
    m = _model()
    d = mujoco.MjData(m)
    mujoco.mj_resetDataKeyframe(m, d, m.key("stand").id)
    mujoco.mj_forward(m, d)
    for leg in "ab":
        foot = d.site(f"foot_{leg}").xpos
        assert foot == pytest.approx([0.0, 0.0, 0.0], abs=1e-12)
    # Both foot spheres touch the floor (radius below z = 0) with zero distance.
    assert d.ncon == 2
    assert [c.dist for c in d.contact] == pytest.approx([0.0, 0.0], abs=1e-12)
    assert m.geom("floor").pos[2] == pytest.approx(-FOOT_RADIUS)


def test_only_the_feet_collide():
    m = _model()
    colliding = {m.geom(i).name for i in range(m.ngeom) if m.geom_contype[i] or m.geom_conaffinity[i]}
    assert colliding == {"floor", "foot_a", "foot_b"}


def test_contact_settings_are_validated():
    with pytest.raises(ValueError, match="time constant"):
        ContactSettings(solref=(0.0005, 1.0), timestep=0.0005)
    with pytest.raises(ValueError, match="timestep"):
        ContactSettings(timestep=0.0)
    m = mujoco.MjModel.from_xml_string(walker_mjcf(contact=ContactSettings(timestep=0.00025)))
    assert m.opt.timestep == pytest.approx(0.00025)


# -- the walker with rolling feet ---------------------------------------------------------


def _rolling(params: FootedParams | None = None) -> mujoco.MjModel:
    return mujoco.MjModel.from_xml_string(rolling_feet_mjcf(params))


@pytest.mark.parametrize("radius", [ROLL_RADIUS, 0.2], ids=["nominal", "radius-0.2"])
def test_rolling_foot_is_a_sphere_of_the_arc_from_params(radius: float):
    """Each foot's sphere is the linkage's rolling arc: its radius, centred on the arc's
    centre (``roll_radius`` up the shank from its end), the site ``foot_<leg>`` there."""
    params = replace(FootedParams(), roll_radius=radius)
    m = _rolling(params)
    shank = footed_linkage(params).segment("shank_stance")
    (knee, _), (centre, _) = shank.points["knee"], shank.points["foot"]
    assert shank.rolls["foot"] == radius
    for leg in "ab":
        geom = m.geom(f"foot_{leg}")
        assert geom.type[0] == mujoco.mjtGeom.mjGEOM_SPHERE
        assert geom.size[0] == pytest.approx(radius)
        assert geom.pos == pytest.approx([0, 0, centre - knee])  # in the shank frame, knee at 0
        assert geom.pos[2] == pytest.approx(radius - params.shank.length)
        assert m.site(f"foot_{leg}").pos == pytest.approx(geom.pos)
    assert m.geom("floor").pos[2] == 0.0


def test_rolling_feet_stand_on_their_lowest_points_at_zero_height():
    m = _rolling()
    d = mujoco.MjData(m)
    mujoco.mj_resetDataKeyframe(m, d, m.key("stand").id)
    mujoco.mj_forward(m, d)
    assert d.qpos[1] == pytest.approx(FootedParams().leg_length)
    assert d.ncon == 2
    for c in d.contact[: d.ncon]:
        assert c.dist == pytest.approx(0.0, abs=1e-12)
        assert c.pos == pytest.approx([0.0, 0.0, 0.0], abs=1e-12)


def test_rolling_feet_share_the_walker_layout_knee_range_and_masses():
    params = replace(FootedParams(), knee_max_flexion=2.0, friction=0.7)
    m = _rolling(params)
    assert tuple(_names(m, "joint", m.njnt)) == JOINTS
    assert tuple(_names(m, "actuator", m.nu)) == MOTORS
    for leg in "ab":
        assert m.joint(f"knee_{leg}").range == pytest.approx([0.0, 2.0])
        assert m.jnt_limited[m.joint(f"knee_{leg}").id]
        assert m.body(f"shank_{leg}").mass[0] == pytest.approx(params.shank.mass)
        geom = m.geom(f"foot_{leg}")
        # Sliding friction only: the sphere rolls freely, without torsional or rolling friction.
        assert geom.friction == pytest.approx([0.7, 0.0, 0.0])
        assert geom.condim[0] == 3
    assert m.body_mass.sum() == pytest.approx(params.total_mass)
    colliding = {m.geom(i).name for i in range(m.ngeom) if m.geom_contype[i] or m.geom_conaffinity[i]}
    assert colliding == {"floor", "foot_a", "foot_b"}


def test_model_mjcf_dispatches_by_the_parameters_model():
    assert model_mjcf(WalkerParams()) == walker_mjcf()
    assert model_mjcf(FootedParams()) == rolling_feet_mjcf()
    assert foot_sphere(WalkerParams()) == FootSphere(FOOT_RADIUS, 0.0, 0.0)
    assert MJCF_MODELS == ("walker", "rolling-feet") and check_mjcf_model("rolling-feet") == "rolling-feet"
    with pytest.raises(ValueError, match="only rolling feet"):
        rolling_feet_mjcf(ANKLE_FEET.default_params)


@pytest.mark.parametrize(
    ("params", "match"),
    [
        (
            ANKLE_FEET.default_params,
            "the 'ankle-feet' gait model has no MuJoCo model: only the walker and rolling-feet",
        ),
        (replace(FootedParams(), feet="ankle"), "the 'ankle-feet' gait model has no MuJoCo model"),
        (CompassParams(), "the 'compass' gait model has no MuJoCo model"),
        (replace(FootedParams(), feet="point"), "got FootedParams with feet='point'"),
    ],
)
def test_a_model_without_mujoco_model_is_refused_in_one_line_naming_it(params, match):
    with pytest.raises(ValueError, match=match) as err:
        model_mjcf(params)
    assert "\n" not in str(err.value)
