"""Human steps on the walker with rolling feet: the subject's body with the model's foot and
knee, an observation holding the person's leg angles with the arc resting on the ground, and
case and reference-step keys that never share a file or a cache entry with the walker's."""

from __future__ import annotations

import hashlib
import json

import numpy as np
import pytest

from ioc_bench.human import LEG_SEGMENTS, human_observation, load_step, measured_mask
from ioc_bench.human.case import REFERENCE_REVISION, HumanCaseSpec, ReferenceStep
from ioc_bench.human.models import HUMAN_MODELS, check_human_model, human_model, subject_params
from ioc_bench.human.observe import leg_angles, model_segments, segment_rmse_deg
from ioc_bench.human.scoring import NOMINAL
from ioc_bench.ioc.problem import IOCProblem
from ioc_bench.model.catalogue import get_model
from ioc_bench.model.feet import ROLLING_FEET, FootedParams
from ioc_bench.model.linkage import pin_gap, point_position
from ioc_bench.model.walker import WALKER, walker_linkage


@pytest.fixture(scope="module")
def step():
    return load_step("WBDS01", "T05")


def test_the_subjects_rolling_feet_body_is_its_walkers_with_the_models_foot_and_knee(step) -> None:
    params = subject_params(step.params, ROLLING_FEET)
    defaults = ROLLING_FEET.default_params
    assert isinstance(params, FootedParams)
    assert (params.feet, params.knee, params.roll_radius) == (defaults.feet, defaults.knee, defaults.roll_radius)
    for name in ("torso", "thigh", "shank", "friction", "max_torque", "knee_max_flexion", "gravity"):
        assert getattr(params, name) == getattr(step.params, name)
    assert params.total_mass == pytest.approx(step.params.total_mass)
    assert subject_params(step.params, WALKER) is step.params
    with pytest.raises(ValueError, match="not 'compass'"):
        subject_params(step.params, get_model("compass"))


def test_only_models_with_the_walkers_leg_segments_are_mapped() -> None:
    assert HUMAN_MODELS == ("walker", "rolling-feet")
    assert human_model("rolling-feet") is ROLLING_FEET and check_human_model("walker") == "walker"
    with pytest.raises(ValueError, match="human steps map to the models walker, rolling-feet, not 'compass'"):
        check_human_model("compass")
    with pytest.raises(ValueError, match="unknown gait model 'nope'"):
        check_human_model("nope")


def test_the_ankle_feet_walker_is_refused_for_the_foot_angle_a_step_lacks(step) -> None:
    with pytest.raises(ValueError, match=r"not 'ankle-feet' \(a person's mapped step has no foot angle") as err:
        check_human_model("ankle-feet")
    assert "\n" not in str(err.value)
    with pytest.raises(ValueError, match="not 'ankle-feet'"):
        subject_params(step.params, get_model("ankle-feet"))
    with pytest.raises(ValueError, match="not 'ankle-feet'"):
        HumanCaseSpec("WBDS01", "T05", ("T04",), "bilevel", model="ankle-feet")


def test_the_rolling_feet_observation_holds_the_persons_angles_and_rests_on_the_ground(step) -> None:
    obs = human_observation(step, model=ROLLING_FEET)
    segments = model_segments(ROLLING_FEET)
    legs = [segments.index(n) for n in LEG_SEGMENTS]
    np.testing.assert_array_equal(obs.q[:, legs, 2], step.angles)
    np.testing.assert_array_equal(obs.v[:, legs, 2], step.rates)
    np.testing.assert_array_equal(leg_angles(obs, ROLLING_FEET), step.angles)
    assert segment_rmse_deg(obs, step, ROLLING_FEET) == 0.0
    assert np.array_equal(obs.measured, measured_mask(model=ROLLING_FEET))
    linkage = ROLLING_FEET.linkage(subject_params(step.params, ROLLING_FEET))
    gaps = np.array([[pin_gap(linkage, pin, qk) for pin in linkage.pins] for qk in obs.q])
    np.testing.assert_allclose(gaps, 0.0, atol=1e-12)  # every joint joined, the arc's anchor at the origin
    shank = linkage.segment("shank_stance")
    radius = shank.rolls["foot"]
    centre = np.array([point_position(shank, "foot", qk) for qk in obs.q[:, segments.index("shank_stance")]])
    bottom = centre - [0.0, radius]  # the arc's lowest point: the contact, on the ground
    np.testing.assert_allclose(bottom[:, 1], 0.0, atol=1e-12)
    np.testing.assert_allclose(bottom[:, 0], radius * step.angles[:, 1], atol=1e-12)  # rolled by the shank's angle
    # The hip stands on the arc, not on the walker's point foot: higher by the arc's roll.
    hip = obs.point(linkage, "thigh_stance", "hip")
    walker_hip = human_observation(step).point(walker_linkage(step.params), "thigh_stance", "hip")
    assert np.all(hip[:, 1] >= walker_hip[:, 1] - 1e-12) and not np.allclose(hip, walker_hip)
    IOCProblem(obs, ("hip", "knee", "dtau"), subject_params(step.params, ROLLING_FEET), step.task, model=ROLLING_FEET)


def test_walker_and_rolling_feet_cases_and_reference_steps_never_share_a_key(step) -> None:
    walker = HumanCaseSpec("WBDS01", "T05", ("T04",), "bilevel")
    feet = HumanCaseSpec("WBDS01", "T05", ("T04",), "bilevel", model="rolling-feet")
    assert walker.key == "bilevel/WBDS01__train-T05__predict-T04__seed0"
    assert feet.key == "bilevel/WBDS01__train-T05__predict-T04__seed0__model-rolling-feet"
    assert feet.features == walker.features == ("hip", "knee", "dtau")
    mine, theirs = {r.key for r in walker.needs()}, {r.key for r in feet.needs()}
    assert len(mine) == len(theirs) == 4 and not mine & theirs
    assert all(r.model == "rolling-feet" for r in feet.needs())
    # The walker's reference key is its parameters, task, knots, starts, seed and revision alone.
    payload = {
        "label": NOMINAL, "params": step.params.to_dict(), "task": step.task.to_dict(), "knots": step.n_knots,
        "starts": 3, "seed": 0, "revision": REFERENCE_REVISION,
    }  # fmt: skip
    expected = hashlib.sha256(json.dumps(payload, sort_keys=True).encode()).hexdigest()[:20]
    assert ReferenceStep(NOMINAL, step, 3, 0).key == expected
    assert ReferenceStep(NOMINAL, step, 3, 0, "rolling-feet").key != expected
    assert ReferenceStep(NOMINAL, step, 3, 0) != ReferenceStep(NOMINAL, step, 3, 0, "rolling-feet")


def test_the_measured_moments_are_the_rolling_feet_models_torques(step) -> None:
    obs = human_observation(step, torques=True, model=ROLLING_FEET)
    np.testing.assert_array_equal(obs.tau, step.torques)
    assert obs.measured.sum() == 8 + 4
