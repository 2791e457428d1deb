"""Starting points for the optimizer: the paper's "rough periodic guess plus small noise".

The rough step has a straight stance leg rotating like an inverted pendulum, a swing leg
swinging forward mirror-wise with its knee flexing in mid-swing, and a slightly leaning
torso. It is kinematically consistent (every pin joined, velocities the exact time
derivative) but not dynamically feasible. Multi-start perturbs its shape and adds smooth
noise to every segment angle, from a seeded generator.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ioc_bench.model.linkage import Linkage, place
from ioc_bench.model.params import WalkerParams

#: Relative size of the multi-start perturbation.
START_NOISE = 0.15


@dataclass(frozen=True)
class GuessShape:
    """The few numbers that shape the rough step."""

    step: float = 0.25
    lean: float = 0.05
    knee_swing: float = 0.5
    knee_stance: float = 0.0


def _angles(linkage: Linkage, params: WalkerParams, shape: GuessShape, s: np.ndarray) -> np.ndarray:
    """(len(s), S) segment angles of the rough step at phases ``s`` in [0, 1]."""
    beta = np.arcsin(np.clip(shape.step / (2 * params.leg_length), -1, 1))
    stance, swing, bump = -beta + 2 * beta * s, beta - 2 * beta * s, np.sin(np.pi * s)
    names = [seg.name for seg in linkage.segments]
    theta = np.zeros((len(s), len(names)))
    theta[:, names.index("torso")] = shape.lean
    theta[:, names.index("thigh_stance")] = stance
    theta[:, names.index("shank_stance")] = stance + shape.knee_stance * bump
    theta[:, names.index("thigh_swing")] = swing - 0.5 * shape.knee_swing * bump
    theta[:, names.index("shank_swing")] = swing + 0.5 * shape.knee_swing * bump
    return theta


def rough_step(
    linkage: Linkage,
    params: WalkerParams,
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
    duration = shape.step / speed
    phase = np.linspace(0.0, 1.0, n_knots)

    def positions(s: np.ndarray) -> np.ndarray:
        theta = _angles(linkage, params, shape, s)
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
    linkage: Linkage, params: WalkerParams, speed: float, n_knots: int, rng: np.random.Generator
) -> dict[str, np.ndarray]:
    """The rough step with its shape and every segment angle randomly perturbed."""
    base = GuessShape()
    shape = GuessShape(
        step=base.step * float(np.exp(rng.normal(0.0, START_NOISE))),
        lean=base.lean + float(rng.normal(0.0, START_NOISE * 0.2)),
        knee_swing=base.knee_swing * float(np.exp(rng.normal(0.0, START_NOISE))),
        knee_stance=abs(float(rng.normal(0.0, START_NOISE * 0.1))),
    )
    return rough_step(linkage, params, speed, n_knots, shape, _smooth_noise(rng, n_knots, len(linkage.segments)))


def _smooth_noise(rng: np.random.Generator, n_knots: int, n_segments: int, modes: int = 3) -> np.ndarray:
    """(T, S) smooth random perturbation: a few sine modes per segment, zero at both ends."""
    s = np.linspace(0.0, 1.0, n_knots)[:, None]
    out = np.zeros((n_knots, n_segments))
    for m in range(1, modes + 1):
        out += rng.normal(0.0, START_NOISE * 0.2 / m, size=(1, n_segments)) * np.sin(m * np.pi * s)
    return out
