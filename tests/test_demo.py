"""The demonstration file: round trip, atomic writes and clear errors on bad files."""

from __future__ import annotations

import json

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp

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


# -- every malformed file is a DemonstrationFileError --------------------------------------


def _meta(arrays):
    return json.loads(str(arrays["meta"]))


def _with_meta(arrays, **changes):
    return arrays | {"meta": np.array(json.dumps(_meta(arrays) | changes))}


@pytest.mark.parametrize(
    ("mutate", "message"),
    [
        (lambda a: a | {"meta": np.array(json.dumps([1, 2]))}, "'meta' header must be a JSON object"),
        (lambda a: _with_meta(a, weights=[1, 1, 1]), "weights must be a JSON object"),
        (lambda a: a | {"traj_q": np.array(1.0)}, "array q has shape"),
        (lambda a: a | {"traj_tau": np.array(1.0)}, "array tau has shape"),
        (lambda a: _with_meta(a, weights=_meta(a)["weights"] | {"hip": float("nan")}), "finite number"),
        (lambda a: _with_meta(a, features=_meta(a)["features"] | {"knee": float("inf")}), "finite number"),
        (lambda a: _with_meta(a, weights=_meta(a)["weights"] | {"hip": -1.0}), "non-negative"),
        (lambda a: _with_meta(a, task={"speed": True}), "speed must be a positive"),
        (lambda a: _with_meta(a, solver={"status": ["x"]}), r"solver: missing field\(s\) success"),
        (lambda a: _with_meta(a, solver=_meta(a)["solver"] | {"iterations": 1.5}), r"solver\.iterations must be"),
        (lambda a: _with_meta(a, solver=_meta(a)["solver"] | {"surprise": 1}), r"solver: unknown field\(s\) surprise"),
        (lambda a: _with_meta(a, multistart={"starts": [], "best": 0}), "multistart.best"),
        (lambda a: _with_meta(a, n_intervals=-1), "n_intervals"),
        (lambda a: a | {"meta": np.array([1.0, 2.0])}, "'meta' header must be one JSON string"),
        (lambda a: a | {"traj_q": a["traj_q"].astype(str)}, "array q must hold numbers"),
        (lambda a: a | {"lam_x": np.zeros((2, 2))}, "array lam_x has shape"),
    ],
)
def test_malformed_contents_are_demonstration_file_errors(nominal_demo, tmp_path, mutate, message):
    bad = tmp_path / "bad.npz"
    np.savez(bad, **mutate(_arrays(nominal_demo.save(tmp_path / "good.npz"))))
    with pytest.raises(DemonstrationFileError, match=message):
        Demonstration.load(bad)


def test_damaged_archives_are_demonstration_file_errors(nominal_demo, tmp_path):
    import zipfile

    good = nominal_demo.save(tmp_path / "good.npz")
    with zipfile.ZipFile(good) as z:
        info = z.getinfo("traj_q.npy")
    data = bytearray(good.read_bytes())
    start = info.header_offset + 30 + len(info.filename) + len(info.extra)
    data[start + 20 : start + 40] = bytes(20)  # damage the compressed member
    corrupted = tmp_path / "corrupted.npz"
    corrupted.write_bytes(bytes(data))
    with pytest.raises(DemonstrationFileError, match="not a readable"):
        Demonstration.load(corrupted)
    renamed = tmp_path / "renamed.npz"
    np.save(tmp_path / "array.npy", np.zeros(3))
    (tmp_path / "array.npy").rename(renamed)
    with pytest.raises(DemonstrationFileError, match="not a zip archive"):
        Demonstration.load(renamed)
    with pytest.raises(DemonstrationFileError, match="is a directory"):
        Demonstration.load(tmp_path)


_json = st.recursive(
    st.none() | st.booleans() | st.integers() | st.floats() | st.text(max_size=6),
    lambda inner: st.lists(inner, max_size=3) | st.dictionaries(st.text(max_size=6), inner, max_size=3),
    max_leaves=8,
)
_arrays_st = st.one_of(
    hnp.arrays(
        dtype=st.sampled_from([np.float64, np.int32, np.bool_, np.dtype("U3")]),
        shape=hnp.array_shapes(min_dims=0, max_dims=3, max_side=4),
    ),
    st.just(np.array("{}")),
)


@pytest.fixture(scope="module")
def good_arrays(nominal_demo, tmp_path_factory):
    return _arrays(nominal_demo.save(tmp_path_factory.mktemp("good") / "good.npz"))


@given(
    kind=st.sampled_from(["meta-field", "meta", "array", "drop", "bytes", "truncate"]),
    key=st.sampled_from(
        ["schema", "weights", "features", "params", "task", "solver", "multistart", "n_intervals", "extra"]
    ),
    member=st.sampled_from(["meta", "traj_dt", "traj_q", "traj_tau", "traj_impulses", "lam_x", "lam_g"]),
    value=_json,
    array=_arrays_st,
    position=st.floats(0, 1),
    noise=st.binary(min_size=1, max_size=16),
)
def test_property_load_returns_a_demonstration_or_raises_demonstration_file_error(
    good_arrays, tmp_path_factory, kind, key, member, value, array, position, noise
):
    """Whatever is done to a good file, loading it never raises anything but DemonstrationFileError."""
    path = tmp_path_factory.mktemp("prop") / "demo.npz"
    arrays = dict(good_arrays)
    if kind == "meta-field":
        arrays = _with_meta(arrays, **{key: value})
    elif kind == "meta":
        arrays["meta"] = np.array(json.dumps(value))
    elif kind == "array":
        arrays[member] = array
    elif kind == "drop":
        arrays.pop(member)
    np.savez_compressed(path, **arrays)
    if kind in ("bytes", "truncate"):
        data = bytearray(path.read_bytes())
        at = int(position * (len(data) - 1))
        data = data[:at] if kind == "truncate" else data[:at] + noise + data[at + len(noise) :]
        path.write_bytes(bytes(data))
    try:
        demo = Demonstration.load(path)
    except DemonstrationFileError:
        return
    assert isinstance(demo, Demonstration)
    assert all(np.isfinite(v) for v in demo.features.values()) and all(v >= 0 for v in demo.weights.values())


def _with_features(arrays, features: dict, weights: dict | None = None):
    meta = json.loads(str(arrays["meta"]))
    meta["features"] = features
    if weights is not None:
        meta["weights"] = weights
    arrays["meta"] = np.array(json.dumps(meta))
    return arrays


def test_a_step_solved_in_a_richer_basis_reads_back_and_a_foreign_feature_does_not(nominal_demo, tmp_path):
    """A demonstration solved in a richer cost basis holds work (and collision) beside the
    model's default features, and weights on them: it reads back (the demonstration cache
    reuses it). A feature the model does not have, or a missing default one, is refused."""
    arrays = _arrays(nominal_demo.save(tmp_path / "good.npz"))
    richer = {**nominal_demo.features, "work": 0.5, "collision": 0.0}
    good = tmp_path / "richer.npz"
    np.savez(good, **_with_features(dict(arrays), richer, {**nominal_demo.weights, "work": 0.2}))
    again = Demonstration.load(good)
    assert again.features == richer and again.weights["work"] == 0.2
    assert again.save(tmp_path / "again.npz") and Demonstration.load(tmp_path / "again.npz").features == richer
    missing = {k: v for k, v in nominal_demo.features.items() if k != "torso"}
    for i, features in enumerate(({**nominal_demo.features, "ankle": 1.0}, missing)):
        bad = tmp_path / f"bad{i}.npz"
        np.savez(bad, **_with_features(dict(arrays), features))
        with pytest.raises(DemonstrationFileError, match="do not match"):
            Demonstration.load(bad)
