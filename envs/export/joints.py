"""One full stride of a demonstration as MuJoCo joint trajectories: named, uniform rate, SI units.

A demonstration is one step at Hermite-Simpson knots, legs named by role, in the model's
dimensionless units. This module makes of it what joint-trajectory tools expect:

- **A full stride.** The step (leg ``a`` in stance, from its heel strike), then the same
  step with the legs' roles exchanged by the gait model's leg swap
  (``GaitModel.roles.swap_segments``, what the optimizer's periodicity and impact use) and
  moved forward by one step length (the swing foot's landing point, or for rolling feet
  the arc's anchor): leg ``b`` in stance, ending at leg ``a``'s next heel strike. Leg ``a``
  keeps its identity throughout (the MuJoCo model's legs are physical).
- **MuJoCo coordinates** of every knot by the environment's own mapping
  (:func:`envs.coordinates.to_generalized`, which :class:`envs.reference.DemoReference` and the
  environment's reset use): ``qpos = [hip x, hip z, torso angle, hip_a, knee_a, hip_b,
  knee_b]`` (``ioc_bench.model.mjcf.JOINTS``), the root being the hip; ``qvel`` its
  rates.
- **Uniform samples** at ``rate`` per second, interpolated as the optimizer's
  Hermite-Simpson collocation assumes the motion between knots: a cubic between
  consecutive knots through their positions and velocities (``scipy``'s
  ``CubicHermiteSpline``), velocities its derivative. For the collocated segment angles
  (and so the joint angles, linear in them) this is the collocation's own interpolation
  (:func:`ioc_bench.trajopt.collocation.interpolate`: one cubic over each interval, which
  meets the midpoint knot's angle and rate by the Hermite and Simpson conditions); for the
  hip point, whose path is no cubic, it keeps position and velocity continuous and through
  every knot (one cubic over each interval from its start would miss the midpoint by up to
  6e-5 leg lengths on the nominal step, and jump there). A sample at the heel strike between
  the steps belongs to the second step (after the impact); the last sample is at or before
  the stride's end.
- **SI units**: a walker whose leg is ``leg_length`` metres under g = 9.81 m/s²
  (``ioc_bench.features.PAPER_GRAVITY``); the default 1 m is the paper's units
  (docs/spec.md, "Units"), in which the cost features are reported. Lengths in m, angles
  in rad, time in s (one model time unit is sqrt(L/g) = 0.319 s for L = 1 m), speeds in
  m/s and rad/s.
"""

from __future__ import annotations

import json
import math
import os
from dataclasses import dataclass
from functools import cached_property
from pathlib import Path
from typing import Any

import numpy as np
from scipy.interpolate import CubicHermiteSpline

from envs.coordinates import to_generalized
from envs.physics import build_model
from envs.reference import demo_linkage
from ioc_bench.demo import Demonstration
from ioc_bench.features import PAPER_GRAVITY
from ioc_bench.fileio import atomic_write
from ioc_bench.model.catalogue import get_model
from ioc_bench.model.gait_model import permutation
from ioc_bench.model.linkage import ground_gap
from ioc_bench.model.mjcf import JOINTS, LEGS
from ioc_bench.paths import check_output_file

#: Samples per second of an export unless asked otherwise.
DEFAULT_RATE = 100.0
#: Most samples per second an export takes (the knots are 0.02-0.04 s apart at 1 m).
MAX_RATE = 10_000.0
#: The walker's leg in metres unless asked otherwise: 1 m, the paper's units.
DEFAULT_LEG_LENGTH = 1.0
#: Interpolation between the knots, as the export's metadata names it.
INTERPOLATION = "cubic-hermite"
#: MuJoCo's joint-type codes (``mjtJoint``), for the names in metadata.
_JOINT_TYPES = {2: "slide", 3: "hinge"}


@dataclass(frozen=True)
class SIUnits:
    """How the model's dimensionless units become SI units.

    Attributes:
        leg_length: the walker's leg, m.
        length: metres per model length unit.
        time: seconds per model time unit.
    """

    leg_length: float
    length: float
    time: float

    @classmethod
    def of(cls, params: Any, leg_length: float = DEFAULT_LEG_LENGTH) -> SIUnits:
        """The units of a walker of ``params`` whose leg is ``leg_length`` metres, under 9.81 m/s².

        Model lengths scale by ``leg_length / params.leg_length`` and accelerations by
        ``9.81 / params.gravity``, so time scales by the square root of their ratio.
        """
        if not (math.isfinite(leg_length) and leg_length > 0):
            raise ValueError(f"leg length must be a positive number of metres, got {leg_length}")
        length = leg_length / float(params.leg_length)
        return cls(leg_length, length, math.sqrt(length * float(params.gravity) / PAPER_GRAVITY))

    def positions(self, qpos: np.ndarray) -> np.ndarray:
        """``qpos`` (..., 7) in SI: the root's x and z in m, angles unchanged (rad)."""
        out = np.array(qpos, dtype=float)
        out[..., :2] *= self.length
        return out

    def velocities(self, qvel: np.ndarray) -> np.ndarray:
        """``qvel`` (..., 7) in SI: m/s for the root's x and z, rad/s for the angles."""
        out = np.array(qvel, dtype=float) / self.time
        out[..., :2] *= self.length
        return out


@dataclass(frozen=True, eq=False)
class StrideKnots:
    """The two steps of a stride at their knots, MuJoCo coordinates in model units.

    Attributes:
        times: (T,) knot times of one step (the second starts at ``duration``).
        qpos, qvel: (2, T, 7): per step, every knot's coordinates, leg ``a`` in stance in
            the first step and swinging in the second.
        step_length: how far the second step is moved forward (model lengths).
    """

    times: np.ndarray
    qpos: np.ndarray
    qvel: np.ndarray
    step_length: float

    @property
    def duration(self) -> float:
        """One step's duration (model time units)."""
        return float(self.times[-1])

    def at(self, t: float) -> tuple[np.ndarray, np.ndarray]:
        """``(qpos, qvel)`` at stride time ``t`` (model units), between knots as the module says.

        The second step from ``duration`` on (after the heel strike); ``t`` is clipped to
        the stride.
        """
        step = 1 if t >= self.duration else 0
        local = min(max(t - step * self.duration, 0.0), self.duration)
        spline = self._splines[step]
        return spline(local), spline(local, 1)

    @cached_property
    def _splines(self) -> tuple[CubicHermiteSpline, CubicHermiteSpline]:
        return tuple(CubicHermiteSpline(self.times, self.qpos[s], self.qvel[s]) for s in range(2))


def stride_knots(demo: Demonstration) -> StrideKnots:
    """The step of ``demo`` and its mirror image, at the knots, in MuJoCo coordinates.

    Raises:
        ValueError: if the demonstration's gait model has no MuJoCo model (its actuators
            are not the MuJoCo walker's).
    """
    link = demo_linkage(demo)
    roles = get_model(demo.model).roles
    tr = demo.trajectory
    swap = permutation(tuple(s.name for s in link.segments), roles.swap_segments)
    foot = link.index(roles.swing_foot[0])
    step_length = float(ground_gap(link.segments[foot], roles.swing_foot[1], tr.q[-1][foot])[0])
    mirrored_q = tr.q[:, swap].copy()
    mirrored_q[:, :, 0] += step_length
    steps = ((tr.q, tr.v), (mirrored_q, tr.v[:, swap]))
    per_step = [[to_generalized(link, q[k], v[k], None, LEGS[0]) for k in range(tr.n_knots)] for q, v in steps]
    qpos, qvel = (np.array([[knot[i] for knot in step] for step in per_step]) for i in range(2))
    return StrideKnots(tr.times, qpos, qvel, step_length)


@dataclass(frozen=True, eq=False)
class JointSeries:
    """A stride sampled uniformly, in SI units, MuJoCo's joint names and order.

    Attributes:
        names: joint names (``ioc_bench.model.mjcf.JOINTS``).
        times: (n,) sample times, s (``i / rate``).
        qpos: (n, 7) positions: m (``rootx``, ``rootz``), rad (the rest).
        qvel: (n, 7) velocities: m/s, rad/s.
        rate: samples per second.
        units: the SI units.
        step_time: when the second step starts (leg ``b``'s heel strike), s.
        stride_time: the stride's duration, s.
        step_length: one step's length, m.
    """

    names: tuple[str, ...]
    times: np.ndarray
    qpos: np.ndarray
    qvel: np.ndarray
    rate: float
    units: SIUnits
    step_time: float
    stride_time: float
    step_length: float

    def column(self, name: str) -> np.ndarray:
        """The positions of joint ``name``."""
        return self.qpos[:, self.names.index(name)]


def check_rate(rate: float) -> float:
    """``rate`` if it is a number of samples per second in (0, :data:`MAX_RATE`], else ``ValueError``."""
    if not (math.isfinite(rate) and 0 < rate <= MAX_RATE):
        raise ValueError(f"rate must be a number of samples per second in (0, {MAX_RATE:g}], got {rate}")
    return float(rate)


def stride_series(
    demo: Demonstration, rate: float = DEFAULT_RATE, leg_length: float = DEFAULT_LEG_LENGTH
) -> JointSeries:
    """One full stride of ``demo`` sampled ``rate`` times per second, in SI units.

    Raises:
        ValueError: for a rate outside (0, :data:`MAX_RATE`], a leg length that is not a
            positive number, or a demonstration of a gait model without a MuJoCo model.
    """
    rate = check_rate(rate)
    units = SIUnits.of(demo.params, leg_length)
    knots = stride_knots(demo)
    stride = 2 * knots.duration * units.time
    times = np.arange(math.floor(stride * rate + 1e-9) + 1) / rate
    samples = [knots.at(t / units.time) for t in times]
    return JointSeries(
        names=JOINTS,
        times=times,
        qpos=units.positions(np.array([s[0] for s in samples])),
        qvel=units.velocities(np.array([s[1] for s in samples])),
        rate=rate,
        units=units,
        step_time=knots.duration * units.time,
        stride_time=stride,
        step_length=knots.step_length * units.length,
    )


def describe(demo: Demonstration, source: str | os.PathLike | None = None) -> dict[str, Any]:
    """What an export says of its demonstration (JSON-able): file, model, weights, speed."""
    return {
        "demonstration": None if source is None else Path(source).name,
        "model": demo.model,
        "weights": {k: v for k, v in demo.weights.items() if v},
        "speed": demo.task.speed,
        "features": demo.features,
    }


def write_qpos(
    demo: Demonstration,
    path: str | os.PathLike,
    rate: float = DEFAULT_RATE,
    leg_length: float = DEFAULT_LEG_LENGTH,
    source: str | os.PathLike | None = None,
) -> tuple[Path, JointSeries]:
    """Write one full stride as LocoMuJoCo-style arrays (``.npz``, atomically); returns the path and the series.

    The arrays (docs/exports.md): ``qpos`` (n, 7) and ``qvel`` (n, 7) in SI units,
    ``joint_names`` (7,), ``frequency`` (Hz), the MuJoCo model's ``njnt`` and ``jnt_type``,
    ``split_points`` ``[0, n]`` (one trajectory) and ``metadata`` (a JSON string: units,
    interpolation, stride, the demonstration). No array needs pickle to load.

    Raises:
        ValueError: for a path that cannot be written, and as :func:`stride_series`.
    """
    path = check_output_file(path)
    series = stride_series(demo, rate, leg_length)
    model = build_model(demo.params)
    names = tuple(model.joint(i).name for i in range(model.njnt))
    if names != series.names:
        raise ValueError(f"the MuJoCo model's joints {names} are not the mapping's {series.names}")
    meta = {
        "source": "ioc-bench export",
        "units": {"length": "m", "angle": "rad", "time": "s", "leg_length_m": leg_length, "gravity": PAPER_GRAVITY},
        "joint_types": [_JOINT_TYPES.get(int(t), str(int(t))) for t in model.jnt_type],
        "interpolation": INTERPOLATION,
        "stride": "leg a (right) in stance from its heel strike, then leg b (left) from its heel strike",
        "step_time_s": series.step_time,
        "stride_time_s": series.stride_time,
        "step_length_m": series.step_length,
        **describe(demo, source),
    }
    arrays = {
        "qpos": series.qpos,
        "qvel": series.qvel,
        "joint_names": np.array(series.names),
        "frequency": np.array(series.rate),
        "njnt": np.array(model.njnt),
        "jnt_type": np.array(model.jnt_type, dtype=np.int64),
        "split_points": np.array([0, len(series.times)]),
        "metadata": np.array(json.dumps(meta, sort_keys=True)),
    }
    atomic_write(path, lambda f: np.savez_compressed(f, **arrays))
    return path, series
