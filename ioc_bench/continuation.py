"""``continue_gait``: an optimal step carried to another task by continuation.

A walker has several families of optima for one cost and task (``docs/human.md``: a
bent-knee family 1.6-3.7 times cheaper than the straighter one). The cheapest of a few cold
starts at each speed may switch family from one speed to the next, so the change it
predicts measures which start won, not what the cost predicts. Continuation follows one
optimum instead: from a solved step, the task moves in small steps of speed (and of step
length, when the task fixes it), each solved warm from the last optimum's primal-dual
solution; a step that fails is halved. The end is the same family's optimum at the new task,
checked for being a local minimum of its own cost when ``verify`` is set.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ioc_bench.demo import Demonstration
from ioc_bench.features import model_features
from ioc_bench.model.catalogue import get_model
from ioc_bench.optimize import optimize_gait
from ioc_bench.task import Task
from ioc_bench.validation import shown

#: Largest change of speed (walker units, sqrt(g L)) per warm solve: about 0.06 m/s on a
#: 0.9 m leg. The treadmill speeds of one subject are 0.03-0.05 apart.
SPEED_STEP = 0.02
#: How many times a failed step is halved before the continuation gives up.
MAX_HALVINGS = 4


@dataclass(frozen=True)
class Continued:
    """The end of a continuation.

    Attributes:
        demo: the optimum at the target task (``demo.solver.success`` False if the
            continuation stopped: then it is the last solve, which failed).
        solves: warm solves made, failed ones included.
        reached: the fraction of the way to the target the last successful solve reached
            (1.0 on success).
    """

    demo: Demonstration
    solves: int
    reached: float

    @property
    def success(self) -> bool:
        return bool(self.demo.solver.success) and self.reached == 1.0


def continue_gait(start: Demonstration, task: Task, speed_step: float = SPEED_STEP, verify: bool = True) -> Continued:
    """Carry the optimum ``start`` (its weights, parameters and model) to ``task``.

    The task moves linearly from ``start.task`` to ``task`` in at most ``speed_step`` of
    speed per solve; both tasks must fix the step length, or neither. Each solve is warm
    from the last optimum. The final optimum is checked for being a local minimum (and
    polished) when ``verify`` is set, as :func:`~ioc_bench.optimize.optimize_gait` does.

    Raises:
        ValueError: ``start`` not a successful solve, a ``task`` that fixes the step length
            where the start's does not (or the reverse), or a ``speed_step`` not > 0.
    """
    if not isinstance(start, Demonstration) or not start.solver.success:
        raise ValueError(f"continuation starts from a successful Demonstration, got {shown(start)}")
    if not isinstance(task, Task) or (task.step_length is None) != (start.task.step_length is None):
        raise ValueError(f"the target task must fix the step length exactly when the start's does, got {shown(task)}")
    if not (isinstance(speed_step, (int, float)) and speed_step > 0):
        raise ValueError(f"speed_step must be a number > 0, got {shown(speed_step)}")
    n = max(1, int(np.ceil(abs(task.speed - start.task.speed) / speed_step - 1e-9)))
    at, done, solves, last = start, 0.0, 0, start
    step = 1.0 / n
    halvings = 0
    while done < 1.0:
        target = min(1.0, done + step)
        final = target >= 1.0 - 1e-12
        last = _solve(at, _between(start.task, task, target), verify and final)
        solves += 1
        if last.solver.success:
            at, done = last, (1.0 if final else target)
            continue
        halvings += 1
        if halvings > MAX_HALVINGS:
            return Continued(last, solves, done)
        step /= 2
    return Continued(last, solves, 1.0)


def _between(a: Task, b: Task, s: float) -> Task:
    """The task a fraction ``s`` of the way from ``a`` to ``b`` (speed and step length linear)."""
    speed = (1 - s) * a.speed + s * b.speed
    if a.step_length is None:
        return Task(speed)
    return Task(speed, (1 - s) * a.step_length + s * b.step_length)


def _solve(at: Demonstration, task: Task, verify: bool) -> Demonstration:
    model = get_model(at.model)
    # A step of a basis beyond the model's default (weights on e.g. ``work``) keeps its basis.
    features = None if set(at.weights) <= set(model_features(model)) else tuple(at.weights)
    return optimize_gait(
        at.weights,
        at.params,
        task,
        init=at,
        workers=1,
        n_intervals=at.n_intervals,
        verify=verify,
        model=model,
        features=features,
    )
