"""Does an estimated cost generalize? Its optimum for another task, against the truth's there.

The paper: "A generative model with a cost function can synthesize new behavior given new
task constraints to test generalizability". For every case, the estimated weights are
solved for the other speed (0.34 for a 0.27 demonstration, 0.27 for 0.34) under the *true*
model and task, warm-started at the true weights' optimum there (the demonstration of the
same weight set and seed at that speed), and compared with it:

- ``trajectory_error``: the paper's trajectory error between the two steps;
- ``excess_cost``: how much more the estimated cost's step costs under the true weights,
  relative, ``(w* . phi(x_est) - w* . phi(x*)) / w* . phi(x*)`` (>= 0 up to the solver's
  tolerance when both lie in one basin).

An exact estimate reproduces the true step (measured: below 1e-9). A failed solve is a
recorded result (``status``), never an exception.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import asdict, dataclass
from typing import Any

import numpy as np

from ioc_bench.bases import forward_basis
from ioc_bench.demo import Demonstration
from ioc_bench.features import evaluate
from ioc_bench.metrics import trajectory_error
from ioc_bench.model.catalogue import get_model
from ioc_bench.model.gait_model import GaitModel
from ioc_bench.task import FAST_SPEED, NOMINAL_SPEED, Task
from ioc_bench.trajopt.forward_problem import SolveRequest, get_forward_problem
from ioc_bench.trajopt.solution import StartPoint
from ioc_bench.weights import full_weights

#: The speed a cost learnt at a speed is tested at.
TRANSFER_SPEEDS = {NOMINAL_SPEED: FAST_SPEED, FAST_SPEED: NOMINAL_SPEED}


def transfer_task(speed: float) -> Task | None:
    """The task a demonstration at ``speed`` transfers to (None: no other speed is defined)."""
    for known, other in TRANSFER_SPEEDS.items():
        if np.isclose(speed, known):
            return Task(other)
    return None


@dataclass(frozen=True)
class Transfer:
    """The estimated cost's optimum at the other speed against the true one there."""

    speed: float
    status: str
    trajectory_error: float
    excess_cost: float

    def to_dict(self) -> dict[str, Any]:
        return asdict(self)


def transfer(
    weights: np.ndarray, features: Sequence[str], truth: Demonstration, *, model: GaitModel | None = None
) -> Transfer:
    """Solve unit ``weights`` over ``features`` for ``truth``'s model, parameters and task,
    warm-started at ``truth`` (the true weights' optimum there), and compare. ``model`` is
    ``truth``'s model if the caller resolved it already (a case has); None looks it up."""
    model = get_model(truth.model) if model is None else model
    forward = get_forward_problem(model, truth.n_intervals, forward_basis(model, (*features, *truth.weights)))
    w = full_weights(np.asarray(weights, dtype=float), features, forward.features)
    duals = (truth.lam_x, truth.lam_g) if truth.lam_x.shape == (forward.n_x,) else (None, None)
    start = StartPoint(forward.vector(truth.trajectory), *duals)
    result = forward.solve(SolveRequest(start, truth.params, truth.task, w))
    if not result.report.success:
        return Transfer(truth.task.speed, result.report.status, float("nan"), float("nan"))
    priced = [f for f in forward.features if truth.weights.get(f, 0.0)]  # the true cost's features
    true_w = np.array([truth.weights[f] for f in priced])
    phi = evaluate(result.trajectory, truth.params, priced, model)
    est_cost = float(true_w @ np.array([phi[f] for f in priced]))
    true_cost = float(true_w @ np.array([truth.features[f] for f in priced]))
    return Transfer(
        speed=truth.task.speed,
        status=result.report.status,
        trajectory_error=trajectory_error(result.trajectory, truth.trajectory),
        excess_cost=(est_cost - true_cost) / true_cost,
    )
