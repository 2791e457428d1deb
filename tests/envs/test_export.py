"""``ioc-bench export``: each format read back (OpenSim's ``.sto`` by a parser of its documented
format, the qpos arrays by NumPy, the Minari dataset by ``minari.load_dataset``) and checked
against the demonstration.

Every test but the last two takes the conftest's ``nominal_demo`` (one single-start solve
per session).
"""

from __future__ import annotations

import json
import math
import sys
from pathlib import Path

import numpy as np
import pytest

from envs.export.joints import MAX_RATE, SIUnits, check_rate, stride_knots, stride_series
from envs.export.opensim import COORDINATES
from envs.export.rollouts import INFO_KEYS, dataset_id
from envs.reference import DemoReference
from ioc_bench import Demonstration
from ioc_bench.cli import main
from ioc_bench.features import COST_FEATURES, PAPER_GRAVITY, TIME_UNIT
from ioc_bench.model.mjcf import JOINTS, LEGS
from ioc_bench.model.params import WalkerParams
from ioc_bench.model.walker import ACTUATORS
from ioc_bench.trajopt.collocation import interpolate

#: The .sto columns that are lengths (m); every other column but time is an angle.
LENGTH_COLUMNS = ("pelvis_tx", "pelvis_ty")
#: Significant digits the .sto writes (so a round trip agrees to about this relative error).
STO_TOLERANCE = 1e-8


def read_sto(path: Path) -> tuple[str, dict[str, str], list[str], np.ndarray]:
    """Parse an OpenSim storage file as OpenSim documents it; angles returned in rad.

    Name line; ``key=value`` lines up to ``endheader``; a tab-separated label line starting
    with ``time``; ``nRows`` tab-separated rows of ``nColumns`` numbers.
    """
    lines = path.read_text().split("\n")
    assert lines[-1] == "", "the file ends with a newline"
    lines = lines[:-1]
    name, header, i = lines[0], {}, 1
    while lines[i] != "endheader":
        key, sep, value = lines[i].partition("=")
        assert sep == "=", f"header line {lines[i]!r} is not key=value"
        header[key] = value
        i += 1
    labels = lines[i + 1].split("\t")
    table = np.array([[float(x) for x in line.split("\t")] for line in lines[i + 2 :]])
    assert header["version"] == "1"
    assert int(header["nRows"]) == table.shape[0]
    assert int(header["nColumns"]) == len(labels) == table.shape[1]
    assert labels[0] == "time"
    assert header["inDegrees"] in ("yes", "no")
    if header["inDegrees"] == "yes":
        for c, label in enumerate(labels[1:], start=1):
            if label not in LENGTH_COLUMNS:
                table[:, c] = np.radians(table[:, c])
    return name, header, labels, table


def _save(demo: Demonstration, folder: Path, name: str = "nominal.npz") -> Path:
    folder.mkdir(parents=True, exist_ok=True)
    return demo.save(folder / name)


def _demo_angles(demo: Demonstration, t: float) -> dict[str, float]:
    """The demonstration's own angles at stride time ``t`` (model units), in OpenSim's names and
    signs: by the collocation's interpolation of its segment angles (``DemoReference``), leg a the
    right, in stance in the first step and swinging in the second."""
    ref = DemoReference.of(demo)
    step = 1 if t >= ref.duration else 0
    local = t - step * ref.duration
    joints, _ = ref.joints(local)
    role = dict(zip(ACTUATORS, joints))
    right, left = ("stance", "swing") if step == 0 else ("swing", "stance")
    state, _ = interpolate(ref.times, ref.theta, ref.dtheta, local)
    return {
        "pelvis_tilt": -state[ref.linkage.index("torso")],
        "hip_flexion_r": -role[f"hip_{right}"],
        "knee_angle_r": -role[f"knee_{right}"],
        "hip_flexion_l": -role[f"hip_{left}"],
        "knee_angle_l": -role[f"knee_{left}"],
    }


def test_sto_round_trip_matches_the_demonstration_over_a_full_stride(nominal_demo, tmp_path, capsys):
    demo_path = _save(nominal_demo, tmp_path)
    out = tmp_path / "stride.sto"
    assert main(["export", str(demo_path), "--format", "sto", "--out", str(out)]) == 0
    assert "stride.sto" in capsys.readouterr().out
    name, header, labels, table = read_sto(out)
    assert name == "Coordinates" and header["inDegrees"] == "no"
    assert labels == ["time", *(c[0] for c in COORDINATES)]
    col = {label: table[:, i] for i, label in enumerate(labels)}
    # time in s at 100 Hz from 0, over one stride: two steps of the demonstration's duration
    step_s = nominal_demo.trajectory.duration * TIME_UNIT
    np.testing.assert_allclose(np.diff(col["time"]), 0.01, atol=1e-9)
    assert col["time"][0] == 0 and 2 * step_s - 0.01 < col["time"][-1] <= 2 * step_s
    # every angle is the demonstration's at that time (the collocation's interpolation), both steps
    ref = DemoReference.of(nominal_demo)
    for row, t in enumerate(col["time"]):
        for label, value in _demo_angles(nominal_demo, t / TIME_UNIT).items():
            assert col[label][row] == pytest.approx(value, abs=STO_TOLERANCE), (label, t)
    assert (col["time"] >= step_s).sum() > 30, "the second (mirrored) step is in the file"
    # ... and at the knots, within linear interpolation of the 100 Hz samples
    knots_s = ref.times * TIME_UNIT
    hip_stance = -(ref.joint_map @ ref.theta[:, : ref.joint_map.shape[1]].T)[0]
    assert np.abs(np.interp(knots_s, col["time"], col["hip_flexion_r"]) - hip_stance).max() < 5e-3
    # units: m and m/s of a 1 m leg under 9.81 m/s^2
    assert col["pelvis_tx"][0] == pytest.approx(ref.qpos[0, 0], abs=STO_TOLERANCE)
    assert col["pelvis_ty"].min() > 0.9 and col["pelvis_ty"].max() < 1.0
    speed = (col["pelvis_tx"][-1] - col["pelvis_tx"][0]) / col["time"][-1]
    assert speed == pytest.approx(nominal_demo.task.speed * math.sqrt(PAPER_GRAVITY), rel=0.02)
    assert np.all(col["knee_angle_r"] <= STO_TOLERANCE) and np.all(col["knee_angle_l"] <= STO_TOLERANCE)


def test_sto_in_degrees_for_another_leg_length(nominal_demo, tmp_path):
    """--leg-length scales lengths by L and times by sqrt(L); --degrees writes inDegrees=yes."""
    demo_path = _save(nominal_demo, tmp_path)
    rows = {}
    for leg, flags in ((1.0, []), (0.9, ["--leg-length", "0.9", "--degrees", "--rate", "50"])):
        out = tmp_path / f"leg{leg}.sto"
        assert main(["export", str(demo_path), "--format", "sto", "--out", str(out), *flags]) == 0
        rows[leg] = read_sto(out)
    (_, h1, labels, one), (_, h9, _, nine) = rows[1.0], rows[0.9]
    assert h9["inDegrees"] == "yes" and h1["inDegrees"] == "no"
    assert np.allclose(np.diff(nine[:, 0]), 0.02)
    np.testing.assert_allclose(nine[0, 1:], one[0, 1:] * [0.9 if c in LENGTH_COLUMNS else 1.0 for c in labels[1:]])
    stride = 2 * nominal_demo.trajectory.duration * TIME_UNIT
    assert stride * math.sqrt(0.9) - 0.02 < nine[-1, 0] <= stride * math.sqrt(0.9)
    raw = (tmp_path / "leg0.9.sto").read_text().split("\n")
    hip = raw[7].split("\t")[labels.index("hip_flexion_r")]
    assert float(hip) == pytest.approx(math.degrees(one[0, labels.index("hip_flexion_r")]), rel=1e-8)


def test_the_stride_is_the_step_and_its_mirror_image(nominal_demo):
    knots = stride_knots(nominal_demo)
    ref = DemoReference.of(nominal_demo)
    np.testing.assert_array_equal(knots.qpos[0], ref.qpos)  # the first step is the env's own mapping
    a, b = (JOINTS.index(f"hip_{leg}") for leg in LEGS)
    np.testing.assert_allclose(knots.qpos[1][:, a], ref.qpos[:, b])  # leg a does in step 2 what b did in step 1
    np.testing.assert_allclose(knots.qpos[1][:, b], ref.qpos[:, a])
    np.testing.assert_allclose(knots.qpos[1][0], knots.qpos[0][-1], atol=1e-9)  # no jump at the heel strike
    shifted = knots.qpos[0][0] + np.eye(7)[0] * 2 * knots.step_length
    np.testing.assert_allclose(knots.qpos[1][-1], shifted, atol=1e-9)  # a stride later, two steps ahead
    assert knots.step_length == pytest.approx(nominal_demo.gait.step_length)
    for step in range(2):  # the interpolation goes through every knot of both steps
        for k, t in enumerate(knots.times):
            q, v = knots.at(min(t + step * knots.duration, (step + 1) * knots.duration - 1e-12))
            np.testing.assert_allclose(q, knots.qpos[step][k], atol=1e-9)
            np.testing.assert_allclose(v, knots.qvel[step][k], atol=1e-9)
    for t in np.linspace(0.0, knots.duration, 301):  # and between them, the angles are the collocation's
        q, v = knots.at(t)
        q_ref, v_ref = interpolate(ref.times, ref.qpos, ref.qvel, t)
        np.testing.assert_allclose(q[2:], q_ref[2:], atol=1e-9)
        np.testing.assert_allclose(v[2:], v_ref[2:], atol=1e-6)


def test_the_velocities_are_the_rates_of_the_positions(nominal_demo):
    """``qvel`` in m/s and rad/s, the derivative of ``qpos`` (central differences at 1 kHz,
    away from the heel strike's jump in velocity)."""
    series = stride_series(nominal_demo, rate=1000.0, leg_length=0.9)
    q, v = series.qpos, series.qvel
    fd = (q[2:] - q[:-2]) * 500.0
    step = int(np.searchsorted(series.times, series.step_time))
    rows = [i for i in range(1, len(q) - 1) if abs(i - step) > 2]
    assert np.all(np.abs(fd[[i - 1 for i in rows]] - v[rows]) <= 5e-3 * np.abs(v).max(axis=0))


def test_qpos_export_holds_named_si_arrays_at_the_rate(nominal_demo, tmp_path):
    demo_path = _save(nominal_demo, tmp_path)
    assert main(["export", str(demo_path), "--format", "qpos"]) == 0
    out = tmp_path / "nominal_qpos.npz"
    with np.load(out, allow_pickle=False) as data:
        arrays = {k: data[k] for k in data.files}
    expected = {"qpos", "qvel", "joint_names", "frequency", "njnt", "jnt_type", "split_points", "metadata"}
    assert set(arrays) == expected
    qpos, qvel, n = arrays["qpos"], arrays["qvel"], len(arrays["qpos"])
    assert qpos.shape == qvel.shape == (n, 7) and n == 83
    assert tuple(arrays["joint_names"]) == JOINTS and float(arrays["frequency"]) == 100.0
    assert arrays["jnt_type"].tolist() == [2, 2, 3, 3, 3, 3, 3] and int(arrays["njnt"]) == 7  # slide, hinge
    assert arrays["split_points"].tolist() == [0, n]
    meta = json.loads(str(arrays["metadata"]))
    assert meta["units"] == {"length": "m", "angle": "rad", "time": "s", "leg_length_m": 1.0, "gravity": 9.81}
    assert meta["interpolation"] == "cubic-hermite" and meta["demonstration"] == "nominal.npz"
    ref = DemoReference.of(nominal_demo)
    np.testing.assert_allclose(qpos[0], ref.qpos[0], atol=1e-12)  # knot 0, leg length 1 m
    units = SIUnits.of(nominal_demo.params)
    np.testing.assert_allclose(qvel[0], units.velocities(ref.qvel[0]), atol=1e-12)
    np.testing.assert_allclose(qvel[0, 0], ref.qvel[0, 0] * math.sqrt(PAPER_GRAVITY))  # m/s
    # the .sto holds the same samples in OpenSim's names and signs
    sto = tmp_path / "nominal.sto"
    assert main(["export", str(demo_path), "--format", "sto"]) == 0
    _, _, labels, table = read_sto(sto)
    for opensim, joint, sign, _ in COORDINATES:
        np.testing.assert_allclose(table[:, labels.index(opensim)], sign * qpos[:, JOINTS.index(joint)], atol=1e-8)


def test_a_folder_of_demonstrations(nominal_demo, tmp_path, capsys):
    """Every *.npz of the folder, each export beside it; the qpos exports are not read back as
    demonstrations when the folder is exported again."""
    folder = tmp_path / "demos"
    for name in ("a.npz", "b.npz"):
        _save(nominal_demo, folder, name)
    for _ in range(2):
        assert main(["export", str(folder), "--format", "qpos", "--json"]) == 0
        reports = [json.loads(line) for line in capsys.readouterr().out.splitlines()]
        assert [Path(r["demo"]).name for r in reports] == ["a.npz", "b.npz"]
    assert sorted(p.name for p in folder.iterdir()) == ["a.npz", "a_qpos.npz", "b.npz", "b_qpos.npz"]
    out = tmp_path / "sto"
    assert main(["export", str(folder), "--format", "sto", "--out", str(out)]) == 0
    assert sorted(p.name for p in out.iterdir()) == ["a.sto", "b.sto"]


@pytest.fixture(scope="module")
def minari_export(nominal_demo, tmp_path_factory):
    """The nominal demonstration exported as a Minari dataset by the command line."""
    pytest.importorskip("minari")
    pytest.importorskip("h5py")
    root = tmp_path_factory.mktemp("minari")
    demo_path = _save(nominal_demo, tmp_path_factory.mktemp("demo"), "nominal 0.27.npz")
    assert main(["export", str(demo_path), "--format", "minari", "--out", str(root)]) == 0
    return root, demo_path


def _episode(root: Path, monkeypatch):
    import minari

    monkeypatch.setenv("MINARI_DATASETS_PATH", str(root))
    dataset = minari.load_dataset("ioc-bench/nominal-0-27-v0")
    assert dataset.total_episodes == 1
    return dataset, next(dataset.iterate_episodes())


def test_minari_dataset_loads_and_replays_the_demonstration(nominal_demo, minari_export, monkeypatch):
    """Its observations follow the demonstration's states as closely as the environment's
    tracking does: the joint angles against the demonstration's at the same phase have the
    closed-loop check's tracking error (the same loop at the env's dt), and the walk starts
    exactly in the demonstration's first state."""
    from envs.checks import closed_loop_replay
    from envs.tracking import TrackingPolicy

    _, ep = _episode(minari_export[0], monkeypatch)
    n = len(ep.actions)
    assert ep.observations.shape == (n + 1, 17) and ep.actions.shape == (n, 4)
    assert n == 1000 and ep.truncations[-1] and not ep.terminations.any()  # Gymnasium's time limit, no fall
    ref = DemoReference.of(nominal_demo)
    np.testing.assert_array_equal(ep.observations[0], np.concatenate([ref.qpos[0][1:], ref.qvel[0], np.zeros(4)]))
    policy = TrackingPolicy(nominal_demo)
    errors = []
    for obs, leg in zip(ep.observations[:-1], ep.infos["stance_leg"][:-1]):
        command = policy.command(obs, {"stance_leg": LEGS[int(leg)]})
        errors.append(command.joints_ref - command.joints)
    errors = np.array(errors)
    strikes = int(ep.infos["heel_strikes"][-1])
    assert strikes >= 5
    check = closed_loop_replay(nominal_demo, steps=strikes, control_dt=None)
    assert check.steps_walked == strikes and check.fall_reason is None
    frames = len(check.times) - 1
    assert np.sqrt(np.mean(errors[:frames] ** 2)) == pytest.approx(check.tracking_rms, rel=1e-6)
    assert np.abs(errors[:frames]).max() == pytest.approx(check.tracking_max, rel=1e-6)
    assert np.sqrt(np.mean(errors**2)) <= 1.5 * check.tracking_rms
    # the hip advances one step length per heel strike
    x = ep.infos["x_position"]
    first = int(np.argmax(ep.infos["heel_strikes"] >= 1))
    last = int(np.argmax(ep.infos["heel_strikes"] >= strikes))
    per_step = (x[last] - x[first]) / (strikes - 1)
    assert per_step == pytest.approx(nominal_demo.gait.step_length, rel=0.1)


def test_minari_infos_carry_the_cost_features(nominal_demo, minari_export, monkeypatch):
    """Each step's feature increments (the env's ``phi_*``), the reward terms that sum to the
    reward, and over the first step features near the demonstration's (the PD feedback adds
    torque; the torque rate is dominated by the feedback's ringing at dt = 0.01, not compared)."""
    dataset, ep = _episode(minari_export[0], monkeypatch)
    n = len(ep.actions)
    assert set(ep.infos) == set(INFO_KEYS)
    assert all(len(v) == n + 1 for v in ep.infos.values())
    assert all(ep.infos[k][0] == 0 for k in INFO_KEYS if k.startswith(("phi_", "reward_")))
    terms = sum(ep.infos[k][1:] for k in INFO_KEYS if k.startswith("reward_"))
    np.testing.assert_allclose(terms, ep.rewards, rtol=1e-12, atol=1e-12)
    first = int(np.argmax(ep.infos["heel_strikes"] >= 1))
    seconds = first * 0.01 * TIME_UNIT
    for feature in ("hip", "knee"):
        assert ep.infos[f"phi_{feature}"][1 : first + 1].sum() / seconds == pytest.approx(
            nominal_demo.features[feature], rel=0.25
        )
    assert all(np.all(ep.infos[f"phi_{f}"] >= 0) for f in COST_FEATURES)
    # the dataset's environment rewards as the dataset does: its actions replayed give its data
    env = dataset.recover_environment()
    np.testing.assert_allclose(env.unwrapped.weights, nominal_demo.weight_vector)
    obs, _ = env.reset(options={"demonstration": nominal_demo})
    for i, action in enumerate(ep.actions[:200]):
        obs, reward, *_ = env.step(action)
        np.testing.assert_array_equal(obs, ep.observations[i + 1])
        assert reward == ep.rewards[i]
    env.close()
    assert "nominal 0.27.npz" in dataset.storage.metadata["description"]


def test_minari_dataset_is_never_overwritten(minari_export, capsys):
    root, demo_path = minari_export
    before = sorted(str(p) for p in root.rglob("*"))
    with pytest.raises(SystemExit) as exc:
        main(["export", str(demo_path), "--format", "minari", "--out", str(root)])
    assert exc.value.code == 2
    err = capsys.readouterr().err.splitlines()
    assert len(err) == 1 and "ioc-bench/nominal-0-27-v0 exists already" in err[0]
    assert sorted(str(p) for p in root.rglob("*")) == before


def test_minari_missing_names_the_extra(nominal_demo, tmp_path, monkeypatch, capsys):
    demo_path = _save(nominal_demo, tmp_path)
    monkeypatch.setitem(sys.modules, "minari", None)  # as if not installed
    with pytest.raises(SystemExit) as exc:
        main(["export", str(demo_path), "--format", "minari", "--out", str(tmp_path / "datasets")])
    assert exc.value.code == 2
    err = capsys.readouterr().err.splitlines()
    assert len(err) == 1 and "pip install 'ioc-bench[export]'" in err[0]
    assert not (tmp_path / "datasets").exists()


# -- without a demonstration ---------------------------------------------------------------------


def test_si_units_of_the_walker():
    units = SIUnits.of(WalkerParams())
    assert units.length == 1.0 and units.time == pytest.approx(1 / math.sqrt(9.81))
    short = SIUnits.of(WalkerParams(), 0.9)
    assert short.length == 0.9 and short.time == pytest.approx(math.sqrt(0.9 / 9.81))
    np.testing.assert_allclose(short.velocities(np.ones(7)), [0.9 / short.time] * 2 + [1 / short.time] * 5)
    for bad in (0.0, -1.0, math.nan, math.inf):
        with pytest.raises(ValueError, match="leg length must be a positive number"):
            SIUnits.of(WalkerParams(), bad)


def test_rates_and_dataset_ids():
    assert check_rate(100) == 100.0 and check_rate(MAX_RATE) == MAX_RATE
    for bad in (0.0, -5.0, math.nan, math.inf, MAX_RATE * 2):
        with pytest.raises(ValueError, match="rate must be a number of samples per second"):
            check_rate(bad)
    assert dataset_id("nominal 0.27") == "ioc-bench/nominal-0-27-v0"
    assert dataset_id("demo-v3") == "ioc-bench/demo-v3-v0"
    assert dataset_id("...") == "ioc-bench/demonstration-v0"
    minari = pytest.importorskip("minari")
    for stem in ("nominal 0.27", "demo-v3", "é_x", "..."):
        namespace, name, version = minari.dataset.minari_dataset.parse_dataset_id(dataset_id(stem))
        assert namespace == "ioc-bench" and version == 0 and name
