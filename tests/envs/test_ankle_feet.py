"""The walker with feet on actuated ankles has no MuJoCo model: every way into MuJoCo (the
replay and its checks, the environment, the stride export) refuses it in one line naming
the model, before any physics. Nothing here solves: the demonstration is made up."""

from __future__ import annotations

import pytest
from synthetic import unsolved_demonstration

from envs.checks import REPLAYABLE_MODELS, check_replayable, replay
from envs.export.joints import stride_knots
from envs.physics import build_model
from envs.planar_walker import PlanarWalkerEnv
from ioc_bench import Demonstration
from ioc_bench.model.feet import ANKLE_FEET

NO_MODEL = "the 'ankle-feet' gait model has no MuJoCo model: only the walker and rolling-feet models have one"
NOT_REPLAYED = "a demonstration of the 'ankle-feet' model cannot be replayed: only the walker and rolling-feet"


@pytest.fixture(scope="module")
def demo() -> Demonstration:
    return unsolved_demonstration(ANKLE_FEET)


def _one_line(make, match: str) -> None:
    with pytest.raises(ValueError, match=match) as err:
        make()
    assert "\n" not in str(err.value)


def test_the_ankle_feet_model_is_not_replayable(demo: Demonstration):
    assert ANKLE_FEET.name not in REPLAYABLE_MODELS
    _one_line(lambda: check_replayable(demo), NOT_REPLAYED)
    _one_line(lambda: replay(demo), NOT_REPLAYED)


def test_the_environment_refuses_its_parameters_and_its_demonstrations(demo: Demonstration, tmp_path):
    _one_line(lambda: build_model(ANKLE_FEET.default_params), NO_MODEL)
    _one_line(lambda: PlanarWalkerEnv(params=ANKLE_FEET.default_params), NO_MODEL)
    _one_line(lambda: PlanarWalkerEnv(demonstration=demo), NO_MODEL)
    path = demo.save(tmp_path / "ankle.npz")
    _one_line(lambda: PlanarWalkerEnv(params=ANKLE_FEET.default_params, demonstration=path), NO_MODEL)


def test_its_stride_is_not_exported(demo: Demonstration):
    _one_line(lambda: stride_knots(demo), NO_MODEL)
