"""The transfer score: does an estimated cost reproduce the truth at the other speed?"""

import numpy as np
import pytest

from ioc_bench import Task, optimize_gait
from ioc_bench.features import COST_FEATURES
from ioc_bench.synthetic.transfer import transfer, transfer_task


@pytest.fixture(scope="module")
def fast_demo():
    demo = optimize_gait("nominal", task=Task(0.34), starts=1, seed=0, workers=1)
    assert demo.solver.success
    return demo


def test_transfer_tasks_pair_the_two_speeds():
    assert transfer_task(0.27).speed == 0.34 and transfer_task(0.34).speed == 0.27
    assert transfer_task(0.30) is None


def test_the_true_weights_transfer_exactly(fast_demo):
    truth = np.array([fast_demo.weights[f] for f in COST_FEATURES])
    moved = transfer(truth, COST_FEATURES, fast_demo)
    assert moved.status == "Solve_Succeeded"
    assert moved.trajectory_error < 1e-8 and abs(moved.excess_cost) < 1e-7


def test_wrong_weights_transfer_worse(fast_demo):
    wrong = np.array([1.0, 10.0, 1.0]) / np.linalg.norm([1.0, 10.0, 1.0])
    moved = transfer(wrong, COST_FEATURES, fast_demo)
    assert moved.trajectory_error > 1e-2 and moved.excess_cost > 1e-3


def test_weights_on_features_outside_the_demonstrations_basis_transfer(fast_demo):
    """An estimate over the energetics basis, scored on an effort-basis truth: work and the
    collision loss at weight 0 transfer exactly as the efforts alone; weight on work does not."""
    features = (*COST_FEATURES, "work", "collision")
    truth = np.array([fast_demo.weights[f] for f in COST_FEATURES] + [0.0, 0.0])
    moved = transfer(truth, features, fast_demo)
    assert moved.status == "Solve_Succeeded"
    assert moved.trajectory_error < 1e-8 and abs(moved.excess_cost) < 1e-7
    off = transfer(np.array([*truth[:3], 0.5, 0.0]), features, fast_demo)
    assert off.trajectory_error > 1e-4 and off.excess_cost > 0
