"""Physics checks on an optimal step, computed independently of the NLP code.

Geometry and Newton-Euler are re-derived here from WalkerParams with plain numpy.
"""

from __future__ import annotations

import numpy as np
import pytest

from ioc_bench.model.params import WalkerParams
from ioc_bench.model.walker import PINS, SEGMENTS


def _u(theta):
    return np.stack([np.sin(theta), np.cos(theta)], axis=-1)


def _offsets(p: WalkerParams) -> dict[tuple[str, str], float]:
    """Distance along each segment's axis from its CoM to its named points."""
    return {
        ("torso", "hip"): -p.torso.com,
        ("thigh", "hip"): p.thigh.com,
        ("thigh", "knee"): p.thigh.com - p.thigh.length,
        ("shank", "knee"): p.shank.com,
        ("shank", "foot"): p.shank.com - p.shank.length,
    }


def _kind(segment: str) -> str:
    return segment.split("_")[0]


def point(traj, params, segment, name, k=slice(None)):
    i = SEGMENTS.index(segment)
    d = _offsets(params)[(_kind(segment), name)]
    q = traj.q[k, i]
    return q[..., :2] + d * _u(q[..., 2])


def point_vel(traj, params, segment, name, v=None, k=slice(None)):
    i = SEGMENTS.index(segment)
    d = _offsets(params)[(_kind(segment), name)]
    q, v = traj.q[k, i], (traj.v if v is None else v)[k, i]
    r = d * _u(q[..., 2])
    return v[..., :2] + v[..., 2:3] * np.stack([r[..., 1], -r[..., 0]], axis=-1)


PIN_POINTS = {
    "hip_stance": (("thigh_stance", "hip"), ("torso", "hip")),
    "hip_swing": (("thigh_swing", "hip"), ("torso", "hip")),
    "knee_stance": (("shank_stance", "knee"), ("thigh_stance", "knee")),
    "knee_swing": (("shank_swing", "knee"), ("thigh_swing", "knee")),
}


def newton_euler(traj, params):
    """(T, S, 3) accelerations from pin forces and torques, re-derived here."""
    masses = {"torso": params.torso, "thigh": params.thigh, "shank": params.shank}
    force = np.zeros(traj.q.shape)
    joint_tau = {
        "hip_stance": traj.tau[:, 0],
        "hip_swing": traj.tau[:, 1],
        "knee_stance": traj.tau[:, 2] + traj.lock[:, 0],
        "knee_swing": traj.tau[:, 3] + traj.lock[:, 1],
    }
    pins = dict(PIN_POINTS) | {"ground": (("shank_stance", "foot"), None)}
    for j, name in enumerate(PINS):
        f = traj.pin_forces[:, j]
        for end, sign in zip(pins[name], (1, -1)):
            if end is None:
                continue
            seg, pt = end
            i = SEGMENTS.index(seg)
            r = point(traj, params, seg, pt) - traj.q[:, i, :2]
            force[:, i, :2] += sign * f
            force[:, i, 2] += sign * (r[:, 1] * f[:, 0] - r[:, 0] * f[:, 1])
    parents = {
        "hip_stance": ("torso", "thigh_stance"),
        "hip_swing": ("torso", "thigh_swing"),
        "knee_stance": ("thigh_stance", "shank_stance"),
        "knee_swing": ("thigh_swing", "shank_swing"),
    }
    for name, (parent, child) in parents.items():
        force[:, SEGMENTS.index(child), 2] += joint_tau[name]
        force[:, SEGMENTS.index(parent), 2] -= joint_tau[name]
    acc = np.zeros_like(force)
    for i, seg in enumerate(SEGMENTS):
        m = masses[_kind(seg)]
        acc[:, i, 0] = force[:, i, 0] / m.mass
        acc[:, i, 1] = force[:, i, 1] / m.mass - params.gravity
        acc[:, i, 2] = force[:, i, 2] / m.inertia
    return acc


def test_newton_euler_matches_recorded_accelerations(nominal_demo):
    acc = newton_euler(nominal_demo.trajectory, nominal_demo.params)
    np.testing.assert_allclose(acc, nominal_demo.trajectory.acc, atol=1e-9)


def test_hermite_simpson_defects_vanish_for_collocated_states(nominal_demo):
    """Angles and angular rates are collocated: their defects vanish to solver tolerance.
    Translations follow from the pins; their defects are the discretization error."""
    traj = nominal_demo.trajectory
    acc = newton_euler(traj, nominal_demo.params)
    h = 2 * traj.dt
    y = np.concatenate([traj.q, traj.v], axis=2)
    f = np.concatenate([traj.v, acc], axis=2)
    k = np.arange(0, traj.n_knots - 2, 2)
    simpson = y[k + 2] - y[k] - h / 6 * (f[k] + 4 * f[k + 1] + f[k + 2])
    hermite = y[k + 1] - (y[k] + y[k + 2]) / 2 - h / 8 * (f[k] - f[k + 2])
    angular = [2, 5]
    assert np.abs(simpson[..., angular]).max() < 1e-7
    assert np.abs(hermite[..., angular]).max() < 1e-7
    translational = [0, 1, 3, 4]
    # Discretization error only: 2e-4 measured here; a lock "kick" artifact gave 2e-2.
    assert np.abs(simpson[..., translational]).max() < 2e-3


def test_pins_hold_at_every_knot(nominal_demo):
    traj, params = nominal_demo.trajectory, nominal_demo.params
    for a, b in PIN_POINTS.values():
        gap = point(traj, params, *a) - point(traj, params, *b)
        vgap = point_vel(traj, params, *a) - point_vel(traj, params, *b)
        assert np.abs(gap).max() < 1e-8
        assert np.abs(vgap).max() < 1e-7
    stance_foot = point(traj, params, "shank_stance", "foot")
    assert np.abs(stance_foot).max() < 1e-8
    assert np.abs(point_vel(traj, params, "shank_stance", "foot")).max() < 1e-7


def _post_impact_velocities(traj):
    """Post-impact segment velocities in pre-impact labels (legs swap at heel strike)."""
    swap = [SEGMENTS.index(s) for s in ("torso", "thigh_swing", "shank_swing", "thigh_stance", "shank_stance")]
    return traj.v[0][swap]


def test_angular_momentum_about_new_contact_is_conserved(nominal_demo):
    traj, params = nominal_demo.trajectory, nominal_demo.params
    contact = point(traj, params, "shank_swing", "foot", k=-1)
    masses = [params.torso, params.thigh, params.shank, params.thigh, params.shank]

    def momentum(v):
        h = 0.0
        for i, m in enumerate(masses):
            r = traj.q[-1, i, :2] - contact
            h += m.mass * (r[1] * v[i, 0] - r[0] * v[i, 1]) + m.inertia * v[i, 2]
        return h

    before, after = momentum(traj.v[-1]), momentum(_post_impact_velocities(traj))
    assert abs(before - after) < 1e-8 * max(1.0, abs(before))
    assert abs(before) > 1e-3  # the check is not vacuous


def test_post_impact_relabelled_state_is_the_start(nominal_demo):
    traj, params = nominal_demo.trajectory, nominal_demo.params
    step = point(traj, params, "shank_swing", "foot", k=-1)
    swap = [SEGMENTS.index(s) for s in ("torso", "thigh_swing", "shank_swing", "thigh_stance", "shank_stance")]
    shifted = traj.q[-1].copy()
    shifted[:, 0] -= step[0]
    np.testing.assert_allclose(traj.q[0][swap], shifted, atol=1e-8)
    assert abs(step[1]) < 1e-8 and step[0] == pytest.approx(traj.duration * nominal_demo.task.speed, rel=1e-8)
    # The paper's lift-off: the old stance foot leaves the ground with zero velocity (its
    # pre-impact position, its post-impact velocity) and the ground only pushes it.
    v = traj.v.copy()
    v[-1] = _post_impact_velocities(traj)
    lift = point_vel(traj, params, "shank_stance", "foot", v=v, k=-1)
    assert np.abs(lift).max() < 1e-8
    assert traj.trail_impulse[1] >= -1e-9
    assert abs(traj.trail_impulse[0]) <= params.friction * traj.trail_impulse[1] + 1e-9


def test_ground_pushes_inside_friction_cone_and_swing_foot_clears(nominal_demo):
    traj, params = nominal_demo.trajectory, nominal_demo.params
    ground = traj.pin_forces[:, PINS.index("ground")]
    assert ground[:, 1].min() >= -1e-9
    assert np.all(np.abs(ground[:, 0]) <= params.friction * ground[:, 1] + 1e-8)
    assert point(traj, params, "shank_swing", "foot")[1:, 1].min() >= -1e-8


def test_knee_lock_is_complementary_and_passive(nominal_demo):
    traj = nominal_demo.trajectory
    flex = np.stack([traj.q[:, 2, 2] - traj.q[:, 1, 2], traj.q[:, 4, 2] - traj.q[:, 3, 2]], axis=1)
    assert flex.min() >= -1e-8  # no hyperextension
    assert traj.lock.min() >= -1e-7  # IPOPT relaxes bounds by 1e-8
    products = traj.lock[:-1] * (flex[:-1] + flex[1:])  # locks act only at full extension, and hold it
    assert products.max() <= 1e-6
    assert nominal_demo.solver.complementarity <= 1e-6
