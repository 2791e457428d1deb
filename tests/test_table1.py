"""The forward problem's must-shows: feasibility from the default start, Table I pattern."""

from __future__ import annotations

import pytest

from ioc_bench import WEIGHT_SETS, Task, optimize_gait
from ioc_bench.table1 import feature_table
from ioc_bench.trajopt.solution import FEASIBILITY_TOL


@pytest.mark.parametrize("speed", [0.27, 0.34])
@pytest.mark.parametrize("weights", list(WEIGHT_SETS))
def test_every_weight_set_solves_from_the_default_start(weights, speed):
    demo = optimize_gait(weights, task=Task(speed), starts=1, seed=0, workers=1)
    assert demo.solver.status == "Solve_Succeeded"
    assert demo.solver.max_violation <= FEASIBILITY_TOL
    assert demo.solver.complementarity <= 1e-6


@pytest.mark.slow
@pytest.mark.parametrize("speed", [0.27, 0.34])
def test_table1_pattern(speed):
    """Each penalised feature is lowest under the weight set that penalises it."""
    table = feature_table(Task(speed), starts=15, seed=0)
    assert all(d.solver.success for d in table.demos.values())
    assert table.pattern == {"hip": True, "knee": True, "dtau": True}, table.markdown()
