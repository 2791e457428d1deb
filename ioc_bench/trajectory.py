"""One step of a walker as numbers: what is observed of it, and the full trajectory.

Knots are uniformly spaced by ``dt`` and include the Hermite-Simpson midpoints (the
paper's indexing: knot ``2i+1`` is the midpoint of interval ``i``), so a step with ``M``
collocation intervals has ``T = 2M + 1`` knots. Knot 0 is just after heel strike, knot
``T-1`` just before the next one.

An :class:`Observation` holds what a gait lab measures: knot times, segment positions and
velocities and joint torques. A :class:`Trajectory` is an observation plus everything the
optimizer also knows (accelerations, constraint forces, lock torques, impulses).
"""

from __future__ import annotations

from dataclasses import dataclass, fields

import numpy as np

from ioc_bench.model.linkage import Linkage, point_position

#: Fields of a trajectory that are not per knot.
_NOT_PER_KNOT = ("impulses", "trail_impulse", "lock_impulses")


@dataclass(frozen=True, eq=False)
class Observation:
    """What is measured of a walking step.

    Attributes:
        dt: uniform time between consecutive knots.
        q: (T, S, 3) segment positions ``x, z, theta`` (S segments, storage order of the
            linkage).
        v: (T, S, 3) segment velocities.
        tau: (T, A) actuated joint torques (A actuators, storage order), or None when the
            torques were not measured.
        measured: which of the step's :meth:`signals` columns were measured (positions,
            then velocities, then torques), or None for all of them (torques only if
            ``tau`` is given). Unmeasured entries of ``q`` and ``v`` still hold values (an
            estimate, e.g. from the measured angles), used only as a solver's first guess;
            :meth:`signals` reports them as NaN, so no metric or tracking term sees them.
            A human step, for example, measures the leg segments' angles and rates only.
    """

    dt: float
    q: np.ndarray
    v: np.ndarray
    tau: np.ndarray | None
    measured: np.ndarray | None = None

    def __post_init__(self) -> None:
        n_knots = np.shape(self.q)[0]
        if not (np.isfinite(self.dt) and self.dt > 0):
            raise ValueError(f"{type(self).__name__.lower()} dt must be positive, got {self.dt}")
        for f in fields(self):
            value = getattr(self, f.name)
            if f.name in ("dt", "measured") or value is None:
                continue
            arr = np.asarray(value, dtype=float)
            if not np.all(np.isfinite(arr)):
                raise ValueError(f"{type(self).__name__.lower()} {f.name} has non-finite values")
            if f.name not in _NOT_PER_KNOT and (arr.ndim == 0 or arr.shape[0] != n_knots):
                raise ValueError(f"{type(self).__name__.lower()} {f.name} has shape {arr.shape}, q has {n_knots} knots")
            object.__setattr__(self, f.name, arr)
        if n_knots < 3 or n_knots % 2 == 0:
            raise ValueError(f"a Hermite-Simpson step needs an odd number >= 3 of knots, got {n_knots}")
        if np.shape(self.v) != np.shape(self.q):
            raise ValueError(f"v has shape {np.shape(self.v)}, q has {np.shape(self.q)}")
        if self.measured is not None:
            object.__setattr__(self, "measured", self._check_mask(self.measured))

    def _check_mask(self, measured: object) -> np.ndarray:
        mask = np.asarray(measured)
        n = 2 * self.q[0].size + (0 if self.tau is None else self.tau.shape[1])
        if mask.dtype != bool or mask.shape != (n,):
            raise ValueError(f"measured must be a boolean mask of {n} signal columns, got {mask.dtype} {mask.shape}")
        if not mask.any():
            raise ValueError("measured marks no signal as measured")
        return mask

    @property
    def n_knots(self) -> int:
        return self.q.shape[0]

    @property
    def times(self) -> np.ndarray:
        return self.dt * np.arange(self.n_knots)

    @property
    def duration(self) -> float:
        return self.dt * (self.n_knots - 1)

    @property
    def n_actuators(self) -> int | None:
        return None if self.tau is None else self.tau.shape[1]

    def point(self, linkage: Linkage, segment: str, point: str) -> np.ndarray:
        """(T, 2) world trajectory of a named segment point."""
        seg = linkage.segment(segment)
        i = linkage.index(segment)
        return np.array([point_position(seg, point, qk[i]) for qk in self.q], dtype=float)

    def signals(self, n_actuators: int | None = None) -> np.ndarray:
        """(T, n) positions, velocities and torques knot by knot; unmeasured torques are NaN
        (``n_actuators`` columns of them)."""
        t = self.n_knots
        tau = self.tau if self.tau is not None else np.full((t, n_actuators or 0), np.nan)
        out = np.concatenate([self.q.reshape(t, -1), self.v.reshape(t, -1), tau], axis=1)
        if self.measured is not None:
            out[:, : self.measured.size][:, ~self.measured] = np.nan
        return out

    def observed(self) -> Observation:
        """Only what is measured of this step (drops everything a trajectory adds)."""
        return Observation(self.dt, self.q, self.v, self.tau, self.measured)

    def with_signals(self, signals: np.ndarray) -> Observation:
        """An observation with the same knots whose signals (:meth:`signals` layout) are given;
        where ``signals`` is NaN (an unmeasured column) this observation's values stay."""
        t, nq = self.n_knots, self.q[0].size
        parts = [self.q.reshape(t, -1), self.v.reshape(t, -1)] + ([] if self.tau is None else [self.tau])
        own = np.concatenate(parts, axis=1)
        given = np.asarray(signals, dtype=float)[:, : own.shape[1]]
        sig = np.where(np.isnan(given), own, given)
        tau = None if self.tau is None else sig[:, 2 * nq :]
        return Observation(
            self.dt, sig[:, :nq].reshape(self.q.shape), sig[:, nq : 2 * nq].reshape(self.v.shape), tau, self.measured
        )


@dataclass(frozen=True, eq=False)
class Trajectory(Observation):
    """A walking step in segment coordinates, with everything the optimizer solved for.

    Attributes:
        acc: (T, S, 3) segment accelerations (Newton-Euler of the pin forces and torques).
        lock: (T, L) passive knee-lock torques (>= 0).
        pin_forces: (T, P, 2) pin constraint forces on each pin's ``a`` segment.
        impulses: (P, 2) pin impulses at heel strike; the contact pin's row is the new
            stance foot's ground impulse.
        trail_impulse: (2,) ground impulse on the trailing (old stance) foot at heel strike.
        lock_impulses: (L,) knee-lock impulses at heel strike.
    """

    acc: np.ndarray = None  # type: ignore[assignment]
    lock: np.ndarray = None  # type: ignore[assignment]
    pin_forces: np.ndarray = None  # type: ignore[assignment]
    impulses: np.ndarray = None  # type: ignore[assignment]
    trail_impulse: np.ndarray = None  # type: ignore[assignment]
    lock_impulses: np.ndarray = None  # type: ignore[assignment]

    def __post_init__(self) -> None:
        if self.measured is not None:
            raise ValueError("a trajectory is fully known: it takes no measured mask")
        missing = [name for name in self.array_names() if getattr(self, name) is None]
        if missing:
            raise ValueError(f"trajectory is missing {missing}")
        super().__post_init__()

    @classmethod
    def array_names(cls) -> tuple[str, ...]:
        """The names of a trajectory's arrays (every field but the measurement mask)."""
        return tuple(f.name for f in fields(cls) if f.name != "measured")

    def to_arrays(self) -> dict[str, np.ndarray]:
        return {name: np.asarray(getattr(self, name), dtype=float) for name in self.array_names()}

    @classmethod
    def from_arrays(cls, arrays: dict[str, np.ndarray]) -> Trajectory:
        return cls(**{name: arrays[name] for name in cls.array_names()})
