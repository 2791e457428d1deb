from __future__ import annotations

import numpy as np
import pytest

from ioc_bench.features import ALL_FEATURES, check_names, evaluate
from ioc_bench.model.walker import walker_linkage


def test_features_follow_their_definitions(nominal_demo):
    traj = nominal_demo.trajectory
    f = evaluate(traj, walker_linkage(nominal_demo.params))
    assert f["hip"] == pytest.approx(np.sum(traj.tau[:, :2] ** 2) * traj.dt, rel=1e-9)
    assert f["knee"] == pytest.approx(np.sum(traj.tau[:, 2:] ** 2) * traj.dt, rel=1e-9)
    dtau = 0.001 * np.sum((np.diff(traj.tau, axis=0) / traj.dt) ** 2) * traj.dt
    assert f["dtau"] == pytest.approx(dtau, rel=1e-9)
    assert f["torso"] == pytest.approx(np.sum(traj.q[:, 0, 2] ** 2) * traj.dt, rel=1e-9)
    step = traj.duration * nominal_demo.task.speed
    assert f["steplen"] == pytest.approx((step - 0.3) ** 2, rel=1e-6)
    assert 0 < f["footheight"] < 0.2
    assert nominal_demo.features == pytest.approx(f, rel=1e-9)


def test_unknown_feature_names_list_valid_ones():
    with pytest.raises(ValueError, match="valid: hip"):
        check_names(["hip", "nope"])
    assert check_names(ALL_FEATURES) == ALL_FEATURES
