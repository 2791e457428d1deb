from __future__ import annotations

import numpy as np
import pytest

from ioc_bench.features import ALL_FEATURES, FEATURES, check_names, evaluate, feature_map, model_features
from ioc_bench.model.compass import COMPASS
from ioc_bench.model.walker import walker_linkage

G = 9.81  # the paper's units: a 1 m, 1 kg walker under g = 9.81 m/s^2


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
