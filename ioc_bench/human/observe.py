"""What is observed of a human step, in the benchmark's :class:`Observation` form.

A gait lab measures the leg segments' angles (and so their rates); WBDS has no trunk
markers, so the torso is unmeasured, and the segments' positions are not measured either
(the stance foot rolls on the ground, the walker's is a pinned point). The observation
holds full ``q`` and ``v`` arrays, because solvers start from them, with a ``measured``
mask marking only the four leg segments' angles and rates: everything else reads NaN in
:meth:`Observation.signals`, so no metric or tracking term sees it.

The observation is of a gait model the step maps to (:mod:`ioc_bench.human.models`; the
walker by default), on the subject's parameters for it: its segments, in its linkage's
order. The unmeasured values are a first guess: the torso upright with the default guess's
lean, segment positions placed from the angles with the stance contact held by the ground
pin at the origin (the walker's point foot there; a rolling foot's arc resting on the
ground, its lowest point the contact, rolled forward by the shank's angle), their rates by
central differences of that placement along the step.

Joint torques are not part of the default observation (a gait lab's moments come from
inverse dynamics of a body with feet and ankles, not this walker); ``torques=True`` is the
stated variant that adds the measured hip and knee moments as the model's torques. Ground
forces are never part of an :class:`Observation` (it has no slot for them); they are
:attr:`HumanStep.forces`, to compare with :func:`walker_ground_force`.
"""

from __future__ import annotations

import numpy as np

from ioc_bench.human.models import subject_params
from ioc_bench.human.step import LEG_SEGMENTS, HumanStep
from ioc_bench.model.gait_model import GaitModel, GuessShape
from ioc_bench.model.linkage import Linkage, place
from ioc_bench.model.walker import ACTUATORS, WALKER
from ioc_bench.trajectory import Observation, Trajectory

#: Torso angle (rad, forward lean) of the unmeasured first guess: the default guess's.
TORSO_GUESS = GuessShape().lean
#: Step fraction of the central differences for the unmeasured position rates.
_H = 1e-4


def model_segments(model: GaitModel = WALKER) -> tuple[str, ...]:
    """The segment names of ``model``'s linkage, in its order (the observation's)."""
    return tuple(s.name for s in model.linkage(model.default_params).segments)


def measured_mask(torques: bool = False, model: GaitModel = WALKER) -> np.ndarray:
    """The signal columns a human step measures on ``model``: the leg segments' angles and
    rates (and, with ``torques``, the four joint torques), in :meth:`Observation.signals` order."""
    segments = model_segments(model)
    n_q = 3 * len(segments)
    mask = np.zeros(2 * n_q + (len(ACTUATORS) if torques else 0), dtype=bool)
    for name in LEG_SEGMENTS:
        i = segments.index(name)
        mask[3 * i + 2] = True
        mask[n_q + 3 * i + 2] = True
    if torques:
        mask[2 * n_q :] = True
    return mask


def human_observation(
    step: HumanStep, torques: bool = False, torso: float = TORSO_GUESS, model: GaitModel = WALKER
) -> Observation:
    """The observation of a human step on ``model`` (see the module docstring).

    Args:
        step: the mapped step.
        torques: add the measured hip and knee moments as the model's torques (a stated
            variant; the default observation has no torques).
        torso: the torso angle of the unmeasured first guess, rad.
        model: a model human steps map to (:data:`~ioc_bench.human.models.HUMAN_MODELS`).

    Raises:
        ValueError: a model human steps do not map to, or ``torques`` for a model whose
            actuators are not the walker's hips and knees.
    """
    linkage = model.linkage(subject_params(step.params, model))
    segments = tuple(s.name for s in linkage.segments)
    if torques and tuple(j.name for j in linkage.actuated) != ACTUATORS:
        raise ValueError(f"the measured moments are the walker's {', '.join(ACTUATORS)}; {model.name!r} has others")
    s = step.fractions
    q = _placed(linkage, segments, step, s, torso)
    ahead = _placed(linkage, segments, step, s + _H, torso)
    behind = _placed(linkage, segments, step, s - _H, torso)
    v = (ahead - behind) / (2 * _H * step.duration)
    legs = [segments.index(name) for name in LEG_SEGMENTS]
    q[:, legs, 2] = step.angles
    v[:, legs, 2] = step.rates
    tau = step.torques.copy() if torques else None
    return Observation(step.dt, q, v, tau, measured_mask(torques, model))


def _placed(
    linkage: Linkage, segments: tuple[str, ...], step: HumanStep, fraction: np.ndarray, torso: float
) -> np.ndarray:
    """(T, S, 3) segment positions from the leg angles at step fractions, the ground pin
    holding the stance contact at the origin (:func:`ioc_bench.model.linkage.place`)."""
    legs = step.leg_angles(fraction)
    theta = np.zeros((len(fraction), len(segments)))
    theta[:, segments.index("torso")] = torso
    for j, name in enumerate(LEG_SEGMENTS):
        theta[:, segments.index(name)] = legs[:, j]
    return np.array([place(linkage, row) for row in theta], dtype=float)


def leg_angles(step: Observation, model: GaitModel = WALKER) -> np.ndarray:
    """(T, 4) the leg segments' angles of any step of ``model`` (walker convention), rad."""
    segments = model_segments(model)
    return step.q[:, [segments.index(name) for name in LEG_SEGMENTS], 2]


def segment_rmse_deg(walker_step: Observation, human: HumanStep | Observation, model: GaitModel = WALKER) -> float:
    """RMSE in degrees of the four leg segments' angles over the knots (both steps of ``model``,
    or ``human`` a person's step).

    Both steps run heel strike to heel strike over the same number of knots, so knots are
    compared at equal fractions of the step.
    """
    mine = leg_angles(walker_step, model)
    theirs = human.angles if isinstance(human, HumanStep) else leg_angles(human, model)
    if mine.shape != theirs.shape:
        raise ValueError(f"cannot compare a step of {mine.shape[0]} knots with one of {theirs.shape[0]}")
    return float(np.degrees(np.sqrt(np.mean((mine - theirs) ** 2))))


def walker_ground_force(trajectory: Trajectory, model: GaitModel = WALKER) -> np.ndarray:
    """(T, 2) the ground's force on ``model``'s stance foot (x forward, z up; a rolling
    foot's acts at the arc's lowest point), body weights (the mass and gravity are 1)."""
    pin = model.linkage(model.default_params).pin_index(model.roles.contact_pin)
    return np.asarray(trajectory.pin_forces)[:, pin, :]
