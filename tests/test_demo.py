"""The demonstration file: round trip, atomic writes and clear errors on bad files."""

from __future__ import annotations

import json

import numpy as np
import pytest

from ioc_bench import Demonstration, DemonstrationFileError


def test_round_trip(nominal_demo, tmp_path):
    path = nominal_demo.save(tmp_path / "demo.npz")
    again = Demonstration.load(path)
    assert again.features == nominal_demo.features
    assert again.weights == nominal_demo.weights
    assert again.params == nominal_demo.params and again.task == nominal_demo.task
    assert again.solver == nominal_demo.solver
    np.testing.assert_array_equal(again.trajectory.q, nominal_demo.trajectory.q)
    np.testing.assert_array_equal(again.lam_g, nominal_demo.lam_g)
    assert [p.name for p in tmp_path.iterdir()] == ["demo.npz"]  # no temporary left behind


def _arrays(path):
    with np.load(path) as data:
        return {k: data[k] for k in data.files}


@pytest.mark.parametrize(
    ("mutate", "message"),
    [
        (lambda a: a.pop("traj_q"), "missing trajectory arrays"),
        (lambda a: a.update(meta=np.array(json.dumps({"schema": 99}))), "schema version 99"),
        (lambda a: a.update(traj_tau=a["traj_tau"][:, :3]), "tau has shape"),
        (lambda a: a.pop("meta"), "missing 'meta'"),
    ],
)
def test_malformed_files_name_the_problem(nominal_demo, tmp_path, mutate, message):
    arrays = _arrays(nominal_demo.save(tmp_path / "good.npz"))
    mutate(arrays)
    bad = tmp_path / "bad.npz"
    np.savez(bad, **arrays)
    with pytest.raises(DemonstrationFileError, match=message):
        Demonstration.load(bad)


def test_missing_and_garbage_files(tmp_path):
    with pytest.raises(DemonstrationFileError, match="not found"):
        Demonstration.load(tmp_path / "nope.npz")
    garbage = tmp_path / "garbage.npz"
    garbage.write_bytes(b"not a zip file")
    with pytest.raises(DemonstrationFileError, match="not a readable"):
        Demonstration.load(garbage)
