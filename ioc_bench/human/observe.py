"""What is observed of a human step, in the benchmark's :class:`Observation` form.

A gait lab measures the leg segments' angles (and so their rates); WBDS has no trunk
markers, so the torso is unmeasured, and the segments' positions are not measured either
(the stance foot rolls on the ground, the walker's is a pinned point). The observation
holds full ``q`` and ``v`` arrays, because solvers start from them, with a ``measured``
mask marking only the four leg segments' angles and rates: everything else reads NaN in
:meth:`Observation.signals`, so no metric or tracking term sees it.

The unmeasured values are a first guess: the torso upright with the default guess's lean,
segment positions placed from the angles with the stance foot pinned at the origin, their
rates by central differences of that placement along the step.

Joint torques are not part of the default observation (a gait lab's moments come from
inverse dynamics of a body with feet and ankles, not this walker); ``torques=True`` is the
stated variant that adds the measured hip and knee moments as walker torques. Ground forces
are never part of an :class:`Observation` (it has no slot for them); they are
:attr:`HumanStep.forces`, to compare with :func:`walker_ground_force`.
"""

from __future__ import annotations

import numpy as np

from ioc_bench.human.step import LEG_SEGMENTS, HumanStep
from ioc_bench.model.gait_model import GuessShape
from ioc_bench.model.linkage import Linkage, place
from ioc_bench.model.walker import PINS, SEGMENTS, walker_linkage
from ioc_bench.trajectory import Observation, Trajectory

#: Torso angle (rad, forward lean) of the unmeasured first guess: the default guess's.
TORSO_GUESS = GuessShape().lean
#: Step fraction of the central differences for the unmeasured position rates.
_H = 1e-4


def measured_mask(torques: bool = False) -> np.ndarray:
    """The signal columns a human step measures: the leg segments' angles and rates (and,
    with ``torques``, the four joint torques), in :meth:`Observation.signals` order."""
    n_q = 3 * len(SEGMENTS)
    mask = np.zeros(2 * n_q + (4 if torques else 0), dtype=bool)
    for name in LEG_SEGMENTS:
        i = SEGMENTS.index(name)
        mask[3 * i + 2] = True
        mask[n_q + 3 * i + 2] = True
    if torques:
        mask[2 * n_q :] = True
    return mask


def human_observation(step: HumanStep, torques: bool = False, torso: float = TORSO_GUESS) -> Observation:
    """The observation of a human step (see the module docstring).

    Args:
        step: the mapped step.
        torques: add the measured hip and knee moments as the walker's torques (a stated
            variant; the default observation has no torques).
        torso: the torso angle of the unmeasured first guess, rad.
    """
    linkage = walker_linkage(step.params)
    s = step.fractions
    q = _placed(linkage, step, s, torso)
    ahead = _placed(linkage, step, s + _H, torso)
    behind = _placed(linkage, step, s - _H, torso)
    v = (ahead - behind) / (2 * _H * step.duration)
    legs = [SEGMENTS.index(name) for name in LEG_SEGMENTS]
    q[:, legs, 2] = step.angles
    v[:, legs, 2] = step.rates
    tau = step.torques.copy() if torques else None
    return Observation(step.dt, q, v, tau, measured_mask(torques))


def _placed(linkage: Linkage, step: HumanStep, fraction: np.ndarray, torso: float) -> np.ndarray:
    """(T, S, 3) segment positions from the leg angles at step fractions, stance foot at 0."""
    legs = step.leg_angles(fraction)
    theta = np.zeros((len(fraction), len(SEGMENTS)))
    theta[:, SEGMENTS.index("torso")] = torso
    for j, name in enumerate(LEG_SEGMENTS):
        theta[:, SEGMENTS.index(name)] = legs[:, j]
    return np.array([place(linkage, row) for row in theta], dtype=float)


def leg_angles(step: Observation) -> np.ndarray:
    """(T, 4) the leg segments' angles of any step (walker convention), rad."""
    return step.q[:, [SEGMENTS.index(name) for name in LEG_SEGMENTS], 2]


def segment_rmse_deg(walker_step: Observation, human: HumanStep | Observation) -> float:
    """RMSE in degrees of the four leg segments' angles over the knots.

    Both steps run heel strike to heel strike over the same number of knots, so knots are
    compared at equal fractions of the step.
    """
    mine = leg_angles(walker_step)
    theirs = human.angles if isinstance(human, HumanStep) else leg_angles(human)
    if mine.shape != theirs.shape:
        raise ValueError(f"cannot compare a step of {mine.shape[0]} knots with one of {theirs.shape[0]}")
    return float(np.degrees(np.sqrt(np.mean((mine - theirs) ** 2))))


def walker_ground_force(trajectory: Trajectory) -> np.ndarray:
    """(T, 2) the ground's force on the walker's stance foot (x forward, z up), body weights
    (the walker's mass and gravity are 1)."""
    return np.asarray(trajectory.pin_forces)[:, PINS.index("ground"), :]
