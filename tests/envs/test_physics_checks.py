"""The physical verdict: the valid demonstration passes every check, and each physically
wrong variant of it fails the check that names what is wrong."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from envs.checks import (
    INEQUALITY_TOL,
    PhysicsCheck,
    inverse_dynamics_check,
    physics_checks,
    replay,
    stance_ground_forces,
)
from envs.tracking import PDGains
from ioc_bench import Demonstration
from ioc_bench.model.walker import PINS, SEGMENTS

NAMES = (
    "inverse_dynamics",
    "time_consistency",
    "ground_normal_force",
    "friction_cone",
    "swing_penetration",
    "knee_range",
)


def _checks(demo: Demonstration) -> dict[str, PhysicsCheck]:
    return {c.name: c for c in physics_checks(demo, inverse_dynamics_check(demo))}


def _variant(demo: Demonstration, **arrays) -> Demonstration:
    """``demo`` with some trajectory fields replaced (new arrays: the fixture is never mutated)."""
    return replace(demo, trajectory=replace(demo.trajectory, **arrays))


def _faster(demo: Demonstration, s: float) -> Demonstration:
    """The same path walked ``s`` times faster: knots s times closer, velocities x s, accelerations x s^2."""
    tr = demo.trajectory
    return _variant(demo, dt=tr.dt / s, v=tr.v * s, acc=tr.acc * s**2)


def _failed(checks: dict[str, PhysicsCheck]) -> set[str]:
    return {name for name, c in checks.items() if not c.passed}


@pytest.fixture(scope="module")
def nominal_checks(nominal_demo: Demonstration) -> dict[str, PhysicsCheck]:
    return _checks(nominal_demo)


def test_the_valid_demonstration_passes_every_check(nominal_checks):
    assert tuple(nominal_checks) == NAMES
    for c in nominal_checks.values():
        assert c.passed, c
        assert c.reason == ""
        assert set(c.to_dict()) == {"name", "value", "limit", "sense", "passed", "quantity", "reason", "knot"}
    # Measured on the nominal step: residual ~2e-11, defect ~3e-12, least normal force
    # 0.82 m g, friction margin 0.44 m g, the swing foot touches at height 0, a locked knee
    # straight to 1e-8 rad.
    assert nominal_checks["ground_normal_force"].value > 0.5
    assert nominal_checks["friction_cone"].value < -0.1


def test_ground_force_from_the_motion_is_the_optimizers(nominal_demo: Demonstration):
    """MuJoCo's inverse dynamics of the motion alone give the optimizer's stance-foot pin force."""
    forces = stance_ground_forces(nominal_demo)
    optimizer = nominal_demo.trajectory.pin_forces[:, PINS.index("ground")]
    assert forces == pytest.approx(optimizer, abs=1e-9)


def test_torques_scaled_by_1_1_fail_the_inverse_dynamics(nominal_demo: Demonstration):
    checks = _checks(_variant(nominal_demo, tau=nominal_demo.trajectory.tau * 1.1))
    assert _failed(checks) == {"inverse_dynamics"}  # the motion, hence its ground force, is unchanged
    c = checks["inverse_dynamics"]
    assert "torques inconsistent with the dynamics" in c.reason
    # The residual is the 10 % added to torques, relative to the peak of the scaled ones.
    assert c.value == pytest.approx(0.1 / 1.1, rel=1e-3)


def test_stretched_knot_spacing_fails_the_time_consistency(nominal_demo: Demonstration):
    checks = _checks(_variant(nominal_demo, dt=nominal_demo.trajectory.dt * 1.05))
    # Knot by knot the inverse dynamics see the same states and accelerations: only the
    # integration over the stretched spacing tells this motion from a real one.
    assert _failed(checks) == {"time_consistency"}
    c = checks["time_consistency"]
    assert "inconsistent with its timing" in c.reason
    # Simpson's defect becomes dy - 1.05 dy: 5 % of the largest interval's motion.
    assert c.value == pytest.approx(0.05, rel=1e-6)


def test_a_pulling_ground_force_fails_the_normal_force_check(nominal_demo: Demonstration, nominal_checks):
    """The step walked three times faster needs a ground that pulls.

    At the knot of its least normal force (mid-stance) the body's centre of mass accelerates
    downwards at 0.18 g (f_z = m (g + a_z) = 0.82 m g): the hip vaults over the stance foot.
    Three times faster, the same path's accelerations are nine times larger, 1.6 g downwards,
    faster than free fall; only a ground pulling the foot down can do that. (The demonstration's
    torques do not fit the faster motion either, so the inverse dynamics fail as well.)
    """
    checks = _checks(_faster(nominal_demo, 3.0))
    normal = checks["ground_normal_force"]
    assert not normal.passed
    assert "ground force pulls the stance foot" in normal.reason
    # Newton's law for the whole body: f_z' / m g = 1 + 9 a_z / g = 9 f_z / m g - 8.
    assert normal.value == pytest.approx(9 * nominal_checks["ground_normal_force"].value - 8, rel=1e-9)
    assert normal.knot == nominal_checks["ground_normal_force"].knot
    assert _failed(checks) == {"ground_normal_force", "friction_cone", "inverse_dynamics"}


def test_a_force_outside_the_friction_cone_fails_the_cone_check(nominal_demo: Demonstration):
    """Twice as fast the ground still pushes (0.29 m g at least) but must push sideways harder
    than friction allows (|f_x| = 1.6 m g against mu f_z = 0.34 m g just after heel strike)."""
    checks = _checks(_faster(nominal_demo, 2.0))
    assert checks["ground_normal_force"].passed
    cone = checks["friction_cone"]
    assert not cone.passed
    assert "leaves the friction cone" in cone.reason


def test_a_walker_below_the_floor_fails_the_penetration_check(nominal_demo: Demonstration):
    """The whole step 1 mm (1e-3 L) lower, as if recorded with a floor offset."""
    q = nominal_demo.trajectory.q.copy()
    q[:, :, 1] -= 1e-3
    checks = _checks(_variant(nominal_demo, q=q))
    assert _failed(checks) == {"swing_penetration"}  # height enters no force
    c = checks["swing_penetration"]
    assert "swing foot penetrates the ground" in c.reason
    assert c.value == pytest.approx(1e-3, rel=1e-6)  # it touched at height 0


def test_a_knee_bent_backwards_fails_the_knee_range(nominal_demo: Demonstration):
    """The stance shank turned 0.01 rad back: its (locked, straight) knee is bent past straight."""
    q = nominal_demo.trajectory.q.copy()
    q[:, SEGMENTS.index("shank_stance"), 2] -= 0.01
    c = _checks(_variant(nominal_demo, q=q))["knee_range"]
    assert not c.passed
    assert "stance knee beyond its range" in c.reason and "past straight" in c.reason
    assert c.value == pytest.approx(0.01, abs=INEQUALITY_TOL)


def test_a_fall_is_reported_not_failed(nominal_demo: Demonstration):
    """Instability is not a physical error: without feedback the walk falls, the verdict passes."""
    report = replay(nominal_demo, steps=3, gains=PDGains(kp=0.0, kd=0.0))
    assert report.closed_loop.steps_walked < 3
    assert report.passed
    assert report.failures == ()
    assert [c["name"] for c in report.to_dict()["checks"]] == list(NAMES)


def test_a_wrong_variant_fails_the_report(nominal_demo: Demonstration):
    report = replay(_variant(nominal_demo, tau=nominal_demo.trajectory.tau * 1.1), steps=1)
    assert not report.passed
    assert [c.name for c in report.failures] == ["inverse_dynamics"]
    assert report.check("inverse_dynamics") is report.failures[0]
    assert not report.to_dict()["passed"]
    assert np.isfinite(report.to_dict()["closed_loop"]["feedback_share"])


def test_a_step_that_cannot_be_replayed_keeps_its_verdict(nominal_demo: Demonstration):
    report = replay(_variant(nominal_demo, dt=nominal_demo.trajectory.dt * 1.05), steps=1)
    assert report.closed_loop is None and report.open_loop is None
    assert "does not move steadily forward" in report.replay_error
    assert [c.name for c in report.failures] == ["time_consistency"]
    assert report.to_dict()["closed_loop"] is None


def test_replay_rejects_no_steps(nominal_demo: Demonstration):
    with pytest.raises(ValueError, match="steps"):
        replay(nominal_demo, steps=0)


def test_the_checks_share_one_compiled_model_and_judge_as_with_their_own(nominal_demo, monkeypatch):
    """One MuJoCo model per replay: the physical checks are handed it, and they give the same
    figures (to the last bit) as with a model each."""
    import envs.physics as physics_module
    from envs.physics import Physics

    own_id = inverse_dynamics_check(nominal_demo)
    own = physics_checks(nominal_demo, own_id)
    builds = []
    original = physics_module.build_model
    monkeypatch.setattr(physics_module, "build_model", lambda *a, **k: builds.append(a) or original(*a, **k))
    shared = Physics.of(nominal_demo.params)
    shared_id = inverse_dynamics_check(nominal_demo, physics=shared)
    checks = physics_checks(nominal_demo, shared_id, physics=shared)
    assert len(builds) == 1
    assert np.array_equal(shared_id.residual, own_id.residual)
    assert [c.to_dict() for c in checks] == [c.to_dict() for c in own]


def test_a_check_refuses_the_physics_of_other_parameters(nominal_demo):
    from envs.physics import Physics

    heavy = Physics.of(nominal_demo.params.with_leg_mass_scale(1.1))
    with pytest.raises(ValueError, match="other parameters"):
        inverse_dynamics_check(nominal_demo, physics=heavy)
