"""How the human track scores weights: the walker's steps they predict against the person's.

Real walking has no true weights, so weights are scored by the steps they make the
subject's walker (or the subject's body on another model the step maps to,
:mod:`ioc_bench.human.models`) take, against the person's steps, in degrees of RMSE over
the four leg segments (:func:`~ioc_bench.human.observe.segment_rmse_deg`). At each speed
of a case:

- the **method**: at a training speed, the estimate's optimal step (``starts`` seeded
  starts, the cheapest feasible optimum kept); at a predicted speed, that optimum carried
  there by continuation (:func:`continue_step`: the walker has several families of optima
  for one cost, and the cheapest of a few cold starts may switch family between speeds),
  with the cheapest of cold starts at the predicted speed reported beside it;
- the **nominal**: all weights equal, what a user without IOC would assume;
- the **floor**: the lowest RMSE of any weights solved there (the estimate, the nominal, the
  fixed floor directions; a run's summary lowers it to anything any case solved there);
- the **copy baseline**: the person's own step at the nearest training speed, unchanged (a
  model-free prediction: people change their leg angles little with speed);
- the **adaptation error**: RMSE between the predicted change (the estimate's step here
  minus its step at that training speed) and the person's change; the copy's is the
  person's change itself (it predicts none);
- the **ground-force error**: RMSE (body weights) of the walker's stance-foot force against
  both of the person's feet together, vertical and fore-aft (the walker has one foot down).

Nothing of the person's step at a speed starts its solves. A failed solve is a recorded
result (its status, RMSE NaN).
"""

from __future__ import annotations

import time
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from ioc_bench.continuation import continue_gait
from ioc_bench.demo import Demonstration
from ioc_bench.human.models import subject_params
from ioc_bench.human.observe import leg_angles, segment_rmse_deg, walker_ground_force
from ioc_bench.human.step import HumanStep
from ioc_bench.model.gait_model import GaitModel
from ioc_bench.model.walker import WALKER
from ioc_bench.optimize import optimize_gait
from ioc_bench.task import Task

#: RMSE difference (deg) below which two fits count as equal.
SKILL_TOL = 1e-6
#: Label of the nominal reference (all weights equal).
NOMINAL = "nominal"
#: Two steps whose stance knee flexion at heel strike differs by more than this (deg) are of
#: different families of optima (the bent-knee family lands at 13-17 deg, the other at about
#: 7, the person at -2 to 3: ``docs/human.md``).
FAMILY_KNEE_DEG = 5.0


@dataclass(frozen=True, eq=False)
class SolvedStep:
    """The walker's optimal step for some weights at one human trial's task.

    Attributes:
        label: whose weights (``estimate``, ``nominal`` or a floor direction).
        status: IPOPT's status of the kept optimum.
        success: whether a feasible optimum was found.
        objective: its weighted cost.
        angles: (T, 4) leg segment angles, rad (None if the solve failed).
        ground_force: (T, 2) the stance foot's ground force, body weights (None if failed).
        wall_time: seconds of the solves.
        step_length: the step's length, leg lengths (NaN if failed).
        solves: forward solves made (starts, or a continuation's warm solves).
    """

    label: str
    status: str
    success: bool
    objective: float
    angles: np.ndarray | None
    ground_force: np.ndarray | None
    wall_time: float
    step_length: float = float("nan")
    solves: int = 0

    @classmethod
    def of(cls, demo: Demonstration, label: str, model: GaitModel, wall_time: float, solves: int) -> SolvedStep:
        """The record of a solved step ``demo`` of ``model``."""
        ok = bool(demo.solver.success)
        return cls(
            label=label,
            status=demo.solver.status,
            success=ok,
            objective=float(demo.solver.objective),
            angles=leg_angles(demo.trajectory, model) if ok else None,
            ground_force=walker_ground_force(demo.trajectory, model) if ok else None,
            wall_time=wall_time,
            step_length=float(demo.gait.step_length) if ok and demo.gait is not None else float("nan"),
            solves=solves,
        )

    @property
    def knee_at_strike_deg(self) -> float:
        """Stance knee flexion at heel strike, deg (what tells the families apart; NaN if failed)."""
        return knee_at_strike_deg(self.angles)

    def rmse_deg(self, step: HumanStep) -> float:
        """RMSE (deg) of the leg segments against the person's ``step`` (NaN if failed)."""
        return rmse_deg(self.angles, step.angles)

    def to_dict(self) -> dict[str, Any]:
        return {
            "label": self.label,
            "status": self.status,
            "success": self.success,
            "objective": self.objective,
            "angles": None if self.angles is None else self.angles.tolist(),
            "ground_force": None if self.ground_force is None else self.ground_force.tolist(),
            "wall_time": self.wall_time,
            "step_length": self.step_length,
            "solves": self.solves,
        }

    @classmethod
    def from_dict(cls, data: dict[str, Any]) -> SolvedStep:
        arrays = {k: None if data[k] is None else np.asarray(data[k], dtype=float) for k in ("angles", "ground_force")}
        return cls(
            str(data["label"]), str(data["status"]), bool(data["success"]), float(data["objective"]), **arrays,
            wall_time=float(data["wall_time"]), step_length=float(data["step_length"]), solves=int(data["solves"]),
        )  # fmt: skip


def solve_step(
    weights: Any,
    step: HumanStep,
    starts: int,
    seed: int,
    label: str = "",
    model: GaitModel = WALKER,
    task: Task | None = None,
    features: Sequence[str] | None = None,
) -> SolvedStep:
    """The cheapest feasible optimum of ``starts`` seeded starts for ``weights`` (over the
    model's cost features, or over ``features``) at ``task`` (``step``'s own task by default)
    on the subject's parameters for ``model`` (:func:`~ioc_bench.human.models.subject_params`;
    the subject's walker by default). ``features``: the cost's basis, as
    :func:`~ioc_bench.optimize.optimize_gait` takes it (default: the model's own)."""
    solved, _ = solve_demo(weights, step, starts, seed, label, model, task, features)
    return solved


def solve_demo(
    weights: Any,
    step: HumanStep,
    starts: int,
    seed: int,
    label: str = "",
    model: GaitModel = WALKER,
    task: Task | None = None,
    features: Sequence[str] | None = None,
) -> tuple[SolvedStep, Demonstration]:
    """:func:`solve_step`, with the optimum itself (to carry it to other speeds)."""
    t0 = time.perf_counter()
    params = subject_params(step.params, model)
    demo = optimize_gait(
        weights, params, task or step.task, starts=starts, seed=seed, workers=1, verify=False, model=model,
        n_intervals=(step.n_knots - 1) // 2, features=features,
    )  # fmt: skip
    return SolvedStep.of(demo, label, model, time.perf_counter() - t0, starts), demo


def continue_step(start: Demonstration, task: Task, label: str, model: GaitModel) -> SolvedStep:
    """The optimum ``start`` carried to ``task`` by continuation
    (:func:`~ioc_bench.continuation.continue_gait`): the same family's step there, checked for
    being a local minimum. A continuation that stopped is a failed step (its status says where)."""
    t0 = time.perf_counter()
    end = continue_gait(start, task)
    solved = SolvedStep.of(end.demo, label, model, time.perf_counter() - t0, end.solves)
    if end.success:
        return solved
    status = f"continuation stopped at {100 * end.reached:.0f} % ({end.demo.solver.status})"
    return SolvedStep(label, status, False, solved.objective, None, None, solved.wall_time, solves=end.solves)


def knee_at_strike_deg(angles: np.ndarray | None) -> float:
    """Stance knee flexion at heel strike (knot 0), deg, from (T, 4) leg angles (NaN if None):
    the shank's angle minus the thigh's in the walker's convention."""
    if angles is None:
        return float("nan")
    a = np.asarray(angles)
    return float(np.degrees(a[0, 1] - a[0, 0]))


def same_family(a: SolvedStep, b: SolvedStep) -> bool | None:
    """Whether two steps land on the same family of optima (stance knee flexion at heel strike
    within :data:`FAMILY_KNEE_DEG`); None when either failed."""
    ka, kb = a.knee_at_strike_deg, b.knee_at_strike_deg
    if not (np.isfinite(ka) and np.isfinite(kb)):
        return None
    return bool(abs(ka - kb) <= FAMILY_KNEE_DEG)


def skill_score(method: float, nominal: float, floor: float) -> float:
    """(nominal - method) / (nominal - floor): 1 at the floor, 0 as good as the nominal,
    negative when worse.

    When the nominal is the floor (within :data:`SKILL_TOL`) nothing could be gained: 0 if
    the method matches it, NaN if it does worse (any number would be arbitrary); such a
    prediction still counts as a loss to the nominal in every summary, which compares the
    RMSEs themselves (:func:`beats`). NaN also when any RMSE is not finite (a failed solve).

    Raises:
        ValueError: ``floor`` above ``method`` or ``nominal`` (it is their minimum or lower).
    """
    values = np.array([method, nominal, floor], dtype=float)
    if not np.all(np.isfinite(values)):
        return float("nan")
    if floor > min(method, nominal) + SKILL_TOL:
        raise ValueError(f"the floor {floor} is above the method's {method} or the nominal {nominal} RMSE")
    span = nominal - floor
    if span > SKILL_TOL:
        return float((nominal - method) / span)
    return 0.0 if method <= nominal + SKILL_TOL else float("nan")


def beats(method: float, other: float) -> bool | None:
    """Whether ``method``'s RMSE is below ``other``'s by more than :data:`SKILL_TOL`; None
    when either is not finite (a failed solve is neither a win nor a loss of the weights,
    and is counted as a failure)."""
    if not (np.isfinite(method) and np.isfinite(other)):
        return None
    return bool(method < other - SKILL_TOL)


def rmse_deg(a: np.ndarray | None, b: np.ndarray | None) -> float:
    """RMSE in degrees of two (T, 4) angle arrays (rad); NaN if either is missing."""
    if a is None or b is None:
        return float("nan")
    return float(np.degrees(np.sqrt(np.mean((np.asarray(a) - np.asarray(b)) ** 2))))


def adaptation_deg(walker_here: SolvedStep, walker_there: SolvedStep, here: HumanStep, there: HumanStep) -> float:
    """RMSE (deg) of the walker's change from ``there`` to ``here`` against the person's."""
    if not (walker_here.success and walker_there.success):
        return float("nan")
    return rmse_deg(walker_here.angles - walker_there.angles, here.angles - there.angles)


def ground_force_error(walker: SolvedStep, step: HumanStep) -> float:
    """RMSE (body weights) of the walker's stance-foot force against both of the person's feet."""
    if not walker.success or walker.ground_force is None:
        return float("nan")
    person = step.forces.total
    if not np.all(np.isfinite(person)):
        return float("nan")
    return float(np.sqrt(np.mean((walker.ground_force - person) ** 2)))


def nearest(steps: Sequence[HumanStep], target: HumanStep) -> HumanStep:
    """Of ``steps``, the one whose speed is nearest ``target``'s (the earlier on ties)."""
    return min(steps, key=lambda s: abs(s.task.speed - target.task.speed))


__all__ = [
    "FAMILY_KNEE_DEG",
    "NOMINAL",
    "SKILL_TOL",
    "SolvedStep",
    "adaptation_deg",
    "beats",
    "continue_step",
    "ground_force_error",
    "knee_at_strike_deg",
    "nearest",
    "rmse_deg",
    "same_family",
    "segment_rmse_deg",
    "skill_score",
    "solve_demo",
    "solve_step",
]
