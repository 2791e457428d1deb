from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from ioc_bench.features import (
    ALL_FEATURES,
    COST_FEATURES,
    DISTRACTORS,
    FEATURES,
    FeatureMap,
    available_features,
    check_names,
    cost_features,
    efforts,
    evaluate,
    feature_map,
    feature_vector,
    model_features,
    step_inputs,
)
from ioc_bench.model.compass import COMPASS
from ioc_bench.model.feet import ANKLE_FEET, ROLLING_FEET
from ioc_bench.model.linkage import joint_moments
from ioc_bench.model.walker import WALKER, walker_linkage
from ioc_bench.trajectory import Observation
from ioc_bench.trajopt.initial_guess import rough_step
from ioc_bench.trajopt.step_problem import StepProblem

G = 9.81  # the paper's units: a 1 m, 1 kg walker under g = 9.81 m/s^2
EPS = 0.3  # W, the work feature's smoothing (docs/spec.md, "Work and collision features")
MODELS = (WALKER, COMPASS, ROLLING_FEET, ANKLE_FEET)
NEW = ("work", "collision")


def test_features_follow_their_definitions(nominal_demo):
    """Re-derived here: per-step sums in SI units of a 1 m, 1 kg walker, per second of step."""
    traj = nominal_demo.trajectory
    f = evaluate(traj, nominal_demo.params)
    n = traj.n_knots - 1  # the sums over T knots are divided by (T - 1) dt
    assert f["hip"] == pytest.approx(G**2 * np.sum(traj.tau[:, :2] ** 2) / n, rel=1e-9)
    assert f["knee"] == pytest.approx(G**2 * np.sum(traj.tau[:, 2:] ** 2) / n, rel=1e-9)
    dtau = 0.001 * G**3 * np.sum(np.diff(traj.tau, axis=0) ** 2) / (traj.dt**2 * n)
    assert f["dtau"] == pytest.approx(dtau, rel=1e-9)
    assert f["torso"] == pytest.approx(np.sum(traj.q[:, 0, 2] ** 2) / n, rel=1e-9)
    step = traj.duration * nominal_demo.task.speed
    assert f["steplen"] == pytest.approx((step - 0.3) ** 2, rel=1e-6)
    assert 0 < f["footheight"] < 0.2
    assert nominal_demo.features == pytest.approx(f, rel=1e-9)


def test_increments_sum_to_the_feature(nominal_demo):
    """The per-knot increments (what the environment rewards) add up to the step's feature."""
    traj = nominal_demo.trajectory
    cols = {"hip": [0, 1], "knee": [2, 3]}
    seconds = traj.duration / np.sqrt(G)
    for name in ("hip", "knee", "dtau"):
        inc = FEATURES[name].increment
        total = sum(inc(traj.tau[t], traj.tau[max(t - 1, 0)], traj.dt, cols) for t in range(traj.n_knots))
        assert total / seconds == pytest.approx(nominal_demo.features[name], rel=1e-12)


def test_feature_gradients_match_finite_differences(nominal_demo):
    traj, params = nominal_demo.trajectory, nominal_demo.params
    fmap = feature_map(n_knots=traj.n_knots)
    x = fmap.inputs(traj)
    jac = fmap.jacobian(traj, params)
    rng = np.random.default_rng(3)
    lpv = np.asarray(walker_linkage(params).parameter_vector(), dtype=float)
    for _ in range(5):
        d = rng.normal(size=x.size) * 1e-6
        d[: traj.n_knots] = d[0]  # the knot spacing moves as one (its copies are chained equal)
        plus = np.asarray(fmap.phi(x + d, lpv)).ravel()
        minus = np.asarray(fmap.phi(x - d, lpv)).ravel()
        assert (plus - minus) / 2 == pytest.approx(jac @ d, rel=1e-5, abs=1e-12)


def test_a_model_without_knees_has_no_knee_feature():
    assert model_features(COMPASS) == ("hip", "dtau", "torso", "steplen", "footheight")


def test_unknown_feature_names_list_valid_ones():
    with pytest.raises(ValueError, match="valid: hip"):
        check_names(["hip", "nope"])
    assert check_names(ALL_FEATURES) == ALL_FEATURES


# -- work and collision, on steps made without a solve -----------------------------------


def rough_observation(model, n_knots: int = 9, seed: int = 0) -> Observation:
    """The optimizer's rough first guess with its angles perturbed (velocities their exact
    derivative; perturbed at the ends too, so the impact changes the speeds) and made-up
    smooth torques: a step with realistic kinematics and no solve."""
    rng = np.random.default_rng(seed)
    params = model.default_params
    link = model.linkage(params)
    s = np.linspace(0.0, 1.0, n_knots)[:, None]
    n_seg = len(link.segments)
    noise = 0.1 * rng.normal(size=(1, n_seg)) * np.cos(np.pi * s) + 0.1 * rng.normal(size=(1, n_seg)) * s**2
    blocks = rough_step(model, params, 0.27, n_knots, noise=noise)
    phase = rng.uniform(0, 2 * np.pi, size=(1, len(link.actuated)))
    tau = 0.05 * np.sin(2 * np.pi * s + phase)
    return Observation(blocks["dt"][0], blocks["q"], blocks["v"], tau)


def joint_rates(model, v: np.ndarray) -> np.ndarray:
    """(T, A) child-minus-parent angular velocity of each actuated joint, from the model's description."""
    link = model.linkage(model.default_params)
    return np.stack([v[:, link.index(j.child), 2] - v[:, link.index(j.parent), 2] for j in link.actuated], axis=1)


def kinetic_energy(model, v: np.ndarray) -> float:
    """(S, 3) segment velocities -> kinetic energy, model units."""
    link = model.linkage(model.default_params)
    m = np.array([seg.mass for seg in link.segments], dtype=float)
    inertia = np.array([seg.inertia for seg in link.segments], dtype=float)
    return float(0.5 * np.sum(m * (v[:, 0] ** 2 + v[:, 1] ** 2) + inertia * v[:, 2] ** 2))


def relabelled(model, v0: np.ndarray) -> np.ndarray:
    """(S, 3) first-knot velocities under the labels of before heel strike (legs swapped)."""
    names = [seg.name for seg in model.linkage(model.default_params).segments]
    partner = {a: b for a, b in model.roles.swap_segments} | {b: a for a, b in model.roles.swap_segments}
    return v0[[names.index(partner.get(n, n)) for n in names]]


def positive_part(p: np.ndarray) -> np.ndarray:
    return (p + np.sqrt(p**2 + EPS**2)) / 2


def test_work_is_the_smoothed_positive_joint_power_of_the_walker():
    traj = rough_observation(WALKER)
    # hip_stance, hip_swing, knee_stance, knee_swing: torso->thigh_stance, torso->thigh_swing,
    # thigh_stance->shank_stance, thigh_swing->shank_swing (segments torso, thigh_stance,
    # shank_stance, thigh_swing, shank_swing)
    w = traj.v[:, :, 2]
    rate = np.stack([w[:, 1] - w[:, 0], w[:, 3] - w[:, 0], w[:, 2] - w[:, 1], w[:, 4] - w[:, 3]], axis=1)
    power = G**1.5 * traj.tau * rate  # W: N m (x9.81) times rad/s (x sqrt(9.81))
    assert np.abs(power).max() > 4 * EPS  # the smoothing is not all there is
    expected = np.sum(positive_part(power)) / (traj.n_knots - 1)  # sum_t dT / T_step with T knots
    assert evaluate(traj, WALKER.default_params, ("work",))["work"] == pytest.approx(expected, rel=1e-12)


def test_collision_is_the_kinetic_energy_heel_strike_removes_from_the_walker():
    traj = rough_observation(WALKER)
    link = walker_linkage()
    m = np.array([seg.mass for seg in link.segments])
    inertia = np.array([seg.inertia for seg in link.segments])
    post = traj.v[0][[0, 3, 4, 1, 2]]  # the legs swap at heel strike

    def energy(v):
        return 0.5 * np.sum(m * (v[:, 0] ** 2 + v[:, 1] ** 2) + inertia * v[:, 2] ** 2)

    seconds = traj.duration / np.sqrt(G)
    expected = G * (energy(traj.v[-1]) - energy(post)) / seconds  # J per second
    assert abs(expected) > 1e-3  # the made-up step does change its speeds at the impact
    assert evaluate(traj, WALKER.default_params, NEW)["collision"] == pytest.approx(expected, rel=1e-12)


@pytest.mark.parametrize("model", MODELS, ids=lambda m: m.name)
def test_work_and_collision_are_defined_for_every_model(model):
    traj = rough_observation(model, seed=1)
    power = G**1.5 * traj.tau * joint_rates(model, traj.v)
    work = np.sum(positive_part(power)) / (traj.n_knots - 1)
    loss = kinetic_energy(model, traj.v[-1]) - kinetic_energy(model, relabelled(model, traj.v[0]))
    collision = G * loss / (traj.duration / np.sqrt(G))
    f = evaluate(traj, model.default_params, available_features(model), model)
    assert f["work"] == pytest.approx(work, rel=1e-12)
    assert f["collision"] == pytest.approx(collision, rel=1e-12, abs=1e-14)
    assert {n: f[n] for n in model_features(model)} == evaluate(
        traj, model.default_params, model_features(model), model
    )


def test_joint_power_is_what_the_joint_moments_do_on_the_segments():
    """Sign convention: a torque acts +tau on the child and -tau on the parent, so its power is
    tau (omega_child - omega_parent). pos(p) - pos(-p) = p, so work(tau) - work(-tau) is the
    net power per second, which must equal the moments' power on the segments."""
    traj = rough_observation(WALKER, seed=2)
    link = walker_linkage()
    moments = np.array(
        [
            joint_moments(link, dict(zip(["hip_stance", "hip_swing", "knee_stance", "knee_swing"], row)))
            for row in traj.tau
        ]
    )
    net_power = G**1.5 * np.sum(moments * traj.v[:, :, 2]) / (traj.n_knots - 1)
    params = WALKER.default_params
    ahead = evaluate(traj, params, ("work",))["work"]
    reversed_ = evaluate(Observation(traj.dt, traj.q, traj.v, -traj.tau), params, ("work",))["work"]
    assert abs(net_power) > 0.1
    assert ahead - reversed_ == pytest.approx(net_power, rel=1e-10)


def test_no_torque_does_no_work_but_the_smoothing():
    traj = rough_observation(WALKER)
    idle = Observation(traj.dt, traj.q, traj.v, np.zeros_like(traj.tau))
    # pos(0) = eps / 2 at each of the 4 joints and T knots, summed with dT and over T_step = (T - 1) dT
    expected = 4 * (EPS / 2) * traj.n_knots / (traj.n_knots - 1)
    assert evaluate(idle, WALKER.default_params, ("work",))["work"] == pytest.approx(expected, rel=1e-12)


def test_an_impact_that_keeps_every_speed_loses_nothing():
    traj = rough_observation(WALKER)
    v = traj.v.copy()
    v[0] = v[-1][[0, 3, 4, 1, 2]]  # after relabelling, the post-impact velocities are the pre-impact ones
    kept = Observation(traj.dt, traj.q, v, traj.tau)
    assert evaluate(kept, WALKER.default_params, ("collision",))["collision"] == pytest.approx(0.0, abs=1e-12)
    v[0] = 0.0  # an impact that stops everything loses all the kinetic energy
    stopped = Observation(traj.dt, traj.q, v, traj.tau)
    all_of_it = G * kinetic_energy(WALKER, v[-1]) / (traj.duration / np.sqrt(G))
    assert evaluate(stopped, WALKER.default_params, ("collision",))["collision"] == pytest.approx(all_of_it, rel=1e-12)


@pytest.mark.parametrize("model", (WALKER, ROLLING_FEET), ids=lambda m: m.name)
def test_the_optimizers_features_are_the_feature_maps(model):
    """The step problem's symbolic phi over the five features equals the compiled map's numbers."""
    traj = rough_observation(model, n_knots=9)
    names = ("hip", "knee", "dtau", *NEW)
    step = StepProblem(model, n_intervals=4, features=names)
    assert step.features == names and step.params.blocks["weights"][1] == (5,)
    x = step.layout.pack({"dt": traj.dt, "q": traj.q, "v": traj.v, "tau": traj.tau})
    p = step.parameter_vector(model.default_params, 0.27, np.ones(5))
    symbolic = np.asarray(step.features_fn(x, p), dtype=float).ravel()
    numeric = evaluate(traj, model.default_params, names, model)
    assert symbolic == pytest.approx([numeric[n] for n in names], rel=1e-12)
    assert StepProblem(model, n_intervals=4).features == model_features(model)


def test_a_step_problem_refuses_features_its_model_lacks():
    with pytest.raises(ValueError, match="has no feature"):
        StepProblem(COMPASS, n_intervals=2, features=("hip", "knee"))


def test_work_is_smooth_where_a_joint_power_is_zero():
    """Where a torque is exactly zero the gradient is the smoothed kink's half slope, finite;
    the Hessian is finite too, and the gradient matches finite differences."""
    traj = rough_observation(WALKER, seed=3)
    tau = traj.tau.copy()
    tau[4, 0] = 0.0  # no hip_stance power at knot 4
    v = traj.v.copy()
    v[6, 3, 2] = v[6, 0, 2]  # no hip_swing rate at knot 6
    traj = Observation(traj.dt, traj.q, v, tau)
    fmap = FeatureMap(WALKER, traj.n_knots, NEW)
    x = fmap.inputs(traj)
    lp = np.asarray(walker_linkage().parameter_vector(), dtype=float)
    jac = fmap.jacobian(traj, WALKER.default_params)
    assert np.all(np.isfinite(jac))
    rate = traj.v[4, 1, 2] - traj.v[4, 0, 2]
    column = fmap.blocks["tau"].start + 4 * 4 + 0
    assert jac[0, column] == pytest.approx(0.5 * G**1.5 * rate / (traj.n_knots - 1), rel=1e-12)
    column = fmap.blocks["tau"].start + 6 * 4 + 1
    assert jac[0, column] == pytest.approx(0.0, abs=1e-15)  # no rate: the torque has no power to change
    for index in range(len(NEW)):
        assert np.all(np.isfinite(np.asarray(fmap.hessian(index)(x, lp), dtype=float)))
    rng = np.random.default_rng(0)
    for _ in range(5):
        d = rng.normal(size=x.size) * 1e-7
        d[: traj.n_knots] = d[0]  # the knot spacing moves as one
        plus = np.asarray(fmap.phi(x + d, lp)).ravel()
        minus = np.asarray(fmap.phi(x - d, lp)).ravel()
        assert (plus - minus) / 2 == pytest.approx(jac @ d, rel=1e-6, abs=1e-12)


def test_work_and_collision_need_the_velocities():
    traj = rough_observation(WALKER)
    link = walker_linkage()
    inputs = step_inputs(WALKER, link, np.full(traj.n_knots, traj.dt), traj.q, traj.tau)
    assert float(feature_vector(inputs, ("hip",))) > 0
    for name in NEW:
        with pytest.raises(ValueError, match="velocities"):
            feature_vector(inputs, (name,))


def test_the_benchmarks_feature_lists_are_unchanged():
    """Demonstrations, weight sets, conditions and boards are keyed on these lists: work and
    collision are offered by name only."""
    assert COST_FEATURES == ("hip", "knee", "dtau")
    assert ALL_FEATURES == ("hip", "knee", "dtau", "torso", "steplen", "footheight")
    assert DISTRACTORS == ("torso", "steplen", "footheight")
    assert cost_features(COMPASS) == ("hip", "dtau")
    assert model_features(ROLLING_FEET) == ALL_FEATURES
    assert cost_features(ANKLE_FEET) == ("hip", "knee", "ankle", "dtau")
    assert model_features(ANKLE_FEET) == ("hip", "knee", "ankle", "dtau", "torso", "steplen", "footheight")
    for model in MODELS:
        assert available_features(model) == model_features(model) + NEW
    assert check_names(NEW) == NEW and all(FEATURES[n].unit == "W" for n in NEW)
    with pytest.raises(ValueError, match="has no feature"):
        evaluate(rough_observation(WALKER), WALKER.default_params, ("ankle",))


def test_collision_pairs_each_post_impact_velocity_with_the_segment_that_has_it():
    """With legs of equal mass the relabelling cannot show in the energy; with a heavier stance
    thigh it does: after heel strike the old swing thigh (the new stance thigh) carries the
    first knot's stance-thigh velocity, and keeps its own mass."""
    traj = rough_observation(WALKER, seed=4)
    link = walker_linkage()
    heavy = replace(link.segments[1], mass=3 * link.segments[1].mass, inertia=2 * link.segments[1].inertia)
    link = replace(link, segments=(link.segments[0], heavy, *link.segments[2:]))
    m = np.array([seg.mass for seg in link.segments], dtype=float)
    inertia = np.array([seg.inertia for seg in link.segments], dtype=float)

    def energy(v):
        return 0.5 * np.sum(m * (v[:, 0] ** 2 + v[:, 1] ** 2) + inertia * v[:, 2] ** 2)

    expected = G * (energy(traj.v[-1]) - energy(traj.v[0][[0, 3, 4, 1, 2]])) / (traj.duration / np.sqrt(G))
    assert abs(expected - G * (energy(traj.v[-1]) - energy(traj.v[0])) / (traj.duration / np.sqrt(G))) > 1e-3
    fmap = FeatureMap(WALKER, traj.n_knots, ("collision",))
    lp = np.asarray(link.parameter_vector(), dtype=float)
    assert float(fmap.phi(fmap.inputs(traj), lp)) == pytest.approx(expected, rel=1e-12)


def test_the_efforts_of_any_model_are_told_by_their_definition():
    """An effort is a default-basis feature with a per-knot increment: the ankle's too."""
    assert efforts(("hip", "ankle", "torso", "work", "dtau", "collision", "nope")) == ("hip", "ankle", "dtau")
    assert all(efforts(model_features(m)) == cost_features(m) for m in MODELS)
