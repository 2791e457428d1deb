"""The benchmark's measurement model: what the IOC observes of a demonstrated step.

A lab measures segment positions and velocities (motion capture) and joint torques
(force plates and inverse dynamics), never the optimizer's accelerations, constraint
forces, lock torques or impulses. A condition may add Gaussian noise of a given fraction
of each signal's span to what is measured, and may leave the torques unmeasured (then an
algorithm must get them from its own model, e.g. by projecting the observation).
"""

from __future__ import annotations

import numpy as np

from ioc_bench.trajectory import Observation, Trajectory
from ioc_bench.trajopt.tracking import signal_spans


def observe(step: Trajectory, noise: float, rng: np.random.Generator, torques: bool = True) -> Observation:
    """What is measured of ``step``: positions, velocities and (if ``torques``) joint torques,
    each signal with Gaussian noise of sigma ``noise`` times its span over the step."""
    seen = step.observed() if torques else Observation(step.dt, step.q, step.v, None)
    if noise <= 0:
        return seen
    sig = seen.signals()
    noisy = sig + rng.normal(0.0, 1.0, size=sig.shape) * noise * signal_spans(seen)
    return seen.with_signals(noisy)
