"""The figures a biomechanist reads off a step: length, duration, cadence, clearance, torques.

Also which inequalities the optimum leans on (:meth:`ForwardProblem.active_bounds`), split into
physical ones (ground contact, joint and torque limits), idle passive elements, and
artificial ones (the transcription's own limits), which a credible walking step must not
touch (``docs/gait_regime.md``).
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass, field
from typing import Any

import numpy as np

from ioc_bench.features import PAPER_GRAVITY
from ioc_bench.model.gait_model import GaitModel, GaitParams
from ioc_bench.task import Task
from ioc_bench.trajectory import Trajectory
from ioc_bench.trajopt.forward_problem import ForwardProblem
from ioc_bench.trajopt.step_problem import StepRules, classify_active

#: Leg length of the human-sized walker the figures are also given for (``docs/spec.md``, "Units"), m.
HUMAN_LEG = 0.9
#: Below this mid-swing foot height (leg lengths) the swing foot scuffs the ground.
SCUFF_HEIGHT = 1e-3


@dataclass(frozen=True)
class GaitFigures:
    """A step's gait figures (model units unless the name says otherwise).

    Attributes:
        step_length: landing distance of the swing foot (leg lengths).
        duration: step duration (units of sqrt(L/g)).
        step_length_m: the step of a walker with a 0.9 m leg, metres.
        cadence: steps per minute of a walker with a 0.9 m leg.
        speed_mps: its speed, m/s.
        max_clearance: highest swing-foot point over the step (leg lengths).
        mid_swing_clearance: lowest swing-foot point over the middle half of the step.
        peak_torques: largest |torque| of each actuator (units of m g L).
        active: active inequalities by kind (``physical``, ``idle``, ``artificial``).
    """

    step_length: float
    duration: float
    step_length_m: float
    cadence: float
    speed_mps: float
    max_clearance: float
    mid_swing_clearance: float
    peak_torques: dict[str, float]
    active: dict[str, dict[str, int]] = field(default_factory=dict)

    @property
    def warnings(self) -> list[str]:
        """What makes the step less than a credible walking step, one line each."""
        out = [f"artificial bound active: {k} ({n} entries)" for k, n in self.active.get("artificial", {}).items()]
        if self.mid_swing_clearance < SCUFF_HEIGHT:
            out.append(f"swing foot scuffs: mid-swing height {self.mid_swing_clearance:.1e} leg lengths")
        return out

    def to_dict(self) -> dict[str, Any]:
        return asdict(self)

    @classmethod
    def from_dict(cls, data: dict[str, Any]) -> GaitFigures:
        return cls(**data)


def gait_figures(
    model: GaitModel,
    params: GaitParams,
    trajectory: Trajectory,
    task: Task,
    active: dict[str, int] | None = None,
) -> GaitFigures:
    """The gait figures of a step; ``active`` as :meth:`ForwardProblem.active_bounds` returns it."""
    linkage = model.linkage(params)
    foot = trajectory.point(linkage, *model.roles.swing_foot)
    t = trajectory.n_knots
    step = trajectory.duration * task.speed
    time_unit = math.sqrt(HUMAN_LEG / PAPER_GRAVITY)
    return GaitFigures(
        step_length=step,
        duration=trajectory.duration,
        step_length_m=step * HUMAN_LEG,
        cadence=60.0 / (trajectory.duration * time_unit),
        speed_mps=task.speed * HUMAN_LEG / time_unit,
        max_clearance=float(foot[:, 1].max()),
        mid_swing_clearance=float(foot[t // 4 : 3 * t // 4 + 1, 1].min()),
        peak_torques={j.name: float(np.abs(trajectory.tau[:, i]).max()) for i, j in enumerate(linkage.actuated)},
        active=classify_active(active or {}),
    )


def solved_gait_figures(
    forward: ForwardProblem, x: np.ndarray, trajectory: Trajectory, params: GaitParams, task: Task, rules: StepRules
) -> GaitFigures:
    """:func:`gait_figures` of a solve, with its active bounds."""
    return gait_figures(forward.model, params, trajectory, task, forward.active_bounds(x, params, task, rules))
