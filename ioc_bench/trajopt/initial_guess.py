"""Starting points for the optimizer: the paper's "rough periodic guess plus small noise".

A gait model describes its rough step (segment angles through the step; see
:attr:`GaitModel.guess_angles`); here it becomes decision variables: segments placed so that
every pin is joined, velocities the exact time derivative, body weight on the stance foot,
a uniform knot spacing. It is kinematically consistent but not dynamically feasible.
Multi-start perturbs its shape and adds smooth noise to every segment angle, from a seeded
generator.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from ioc_bench.model.gait_model import GaitModel, GaitParams, GuessShape
from ioc_bench.model.linkage import place

#: Relative size of the multi-start perturbation.
START_NOISE = 0.15
#: Step lengths the perturbed starts spread over (log-stratified) when the task leaves it free.
STEP_RANGE = (0.2, 0.8)


def rough_step(
    model: GaitModel,
    params: GaitParams,
    speed: float,
    n_knots: int,
    shape: GuessShape = GuessShape(),
    noise: np.ndarray | None = None,
) -> dict[str, np.ndarray]:
    """Decision-variable blocks (``dt``, ``q``, ``v``, ``force``) of a rough step.

    Args:
        noise: optional (T, S) perturbation of every segment angle; it is interpolated
            in phase so that velocities stay the exact derivative of positions.
    """
    linkage = model.linkage(params)
    duration = shape.step / speed
    phase = np.linspace(0.0, 1.0, n_knots)

    def positions(s: np.ndarray) -> np.ndarray:
        theta = model.guess_angles(linkage, params, shape, s)
        if noise is not None:
            theta = theta + np.stack([np.interp(s, phase, col) for col in noise.T], axis=1)
        return np.array([place(linkage, th) for th in theta])

    eps = 1e-6
    q = positions(phase)
    v = (positions(phase + eps) - positions(phase - eps)) / (2 * eps * duration)
    force = np.zeros((n_knots, len(linkage.pins), 2))
    grounded = [i for i, p in enumerate(linkage.pins) if p.b is None]
    force[:, grounded, 1] = params.total_mass * params.gravity
    return {"dt": np.full(n_knots, duration / (n_knots - 1)), "q": q, "v": v, "force": force}


def perturbed_step(
    model: GaitModel,
    params: GaitParams,
    speed: float,
    n_knots: int,
    rng: np.random.Generator,
    base: GuessShape = GuessShape(),
) -> dict[str, np.ndarray]:
    """The rough step ``base`` with its shape and every segment angle randomly perturbed."""
    shape = replace(
        base,
        step=base.step * float(np.exp(rng.normal(0.0, START_NOISE))),
        lean=base.lean + float(rng.normal(0.0, START_NOISE * 0.2)),
        knee_swing=base.knee_swing * float(np.exp(rng.normal(0.0, START_NOISE))),
        knee_stance=abs(float(rng.normal(0.0, START_NOISE * 0.1))),
    )
    n_segments = len(model.linkage(params).segments)
    return rough_step(model, params, speed, n_knots, shape, _smooth_noise(rng, n_knots, n_segments))


def multistart_guesses(
    model: GaitModel,
    params: GaitParams,
    speed: float,
    step_length: float | None,
    n_knots: int,
    starts: int,
    seed: int,
) -> list[tuple[str, dict[str, np.ndarray]]]:
    """The paper's multi-start: a rough periodic guess, then ``starts - 1`` perturbed ones.

    With the step length free, the perturbed starts spread their step lengths over
    :data:`STEP_RANGE` (log-stratified, one stratum per start, jittered), so that short and
    long steps are both tried; every start's shape and angles are perturbed as in
    :func:`perturbed_step`. Returns ``(origin, blocks)`` pairs; start ``i`` draws from
    ``numpy.random.default_rng([seed, i])``.
    """
    base = GuessShape() if step_length is None else GuessShape(step=step_length)
    out = [("rough guess", rough_step(model, params, speed, n_knots, base))]
    lo, hi = np.log(STEP_RANGE[0]), np.log(STEP_RANGE[1])
    for i in range(1, starts):
        rng = np.random.default_rng([seed, i])
        if step_length is None:
            u = (i - 1 + rng.uniform()) / max(starts - 1, 1)
            base = GuessShape(step=float(np.exp(lo + u * (hi - lo))))
        guess = perturbed_step(model, params, speed, n_knots, rng, base)
        out.append((f"perturbed (seed {seed}, start {i})", guess))
    return out


def _smooth_noise(rng: np.random.Generator, n_knots: int, n_segments: int, modes: int = 3) -> np.ndarray:
    """(T, S) smooth random perturbation: a few sine modes per segment, zero at both ends."""
    s = np.linspace(0.0, 1.0, n_knots)[:, None]
    out = np.zeros((n_knots, n_segments))
    for m in range(1, modes + 1):
        out += rng.normal(0.0, START_NOISE * 0.2 / m, size=(1, n_segments)) * np.sin(m * np.pi * s)
    return out
