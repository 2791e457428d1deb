"""One step of the walker as numbers: the segment-based trajectory every module shares.

Knots are uniformly spaced by ``dt`` and include the Hermite-Simpson midpoints (the
paper's indexing: knot ``2i+1`` is the midpoint of interval ``i``), so a trajectory with
``M`` collocation intervals has ``T = 2M + 1`` knots. Knot 0 is just after heel strike,
knot ``T-1`` just before the next one.
"""

from __future__ import annotations

from dataclasses import dataclass, fields

import numpy as np

from ioc_bench.model.linkage import Linkage, point_position


@dataclass(frozen=True, eq=False)
class Trajectory:
    """A walking step in segment coordinates.

    Attributes:
        dt: uniform time between consecutive knots.
        q: (T, S, 3) segment positions ``x, z, theta`` (S segments, storage order of the
            linkage).
        v: (T, S, 3) segment velocities.
        acc: (T, S, 3) segment accelerations (Newton-Euler of the pin forces and torques).
        tau: (T, A) actuated joint torques (A actuators, storage order).
        lock: (T, L) passive knee-lock torques (>= 0).
        pin_forces: (T, P, 2) pin constraint forces on each pin's ``a`` segment.
        impulses: (P, 2) pin impulses at heel strike; the contact pin's row is the new
            stance foot's ground impulse.
        lock_impulses: (L,) knee-lock impulses at heel strike.
    """

    dt: float
    q: np.ndarray
    v: np.ndarray
    acc: np.ndarray
    tau: np.ndarray
    lock: np.ndarray
    pin_forces: np.ndarray
    impulses: np.ndarray
    lock_impulses: np.ndarray

    def __post_init__(self) -> None:
        n_knots = np.shape(self.q)[0]
        for f in fields(self):
            value = getattr(self, f.name)
            if f.name == "dt":
                if not (np.isfinite(value) and value > 0):
                    raise ValueError(f"trajectory dt must be positive, got {value}")
                continue
            arr = np.asarray(value, dtype=float)
            if not np.all(np.isfinite(arr)):
                raise ValueError(f"trajectory {f.name} has non-finite values")
            if f.name not in ("impulses", "lock_impulses") and arr.shape[0] != n_knots:
                raise ValueError(f"trajectory {f.name} has {arr.shape[0]} knots, q has {n_knots}")
            object.__setattr__(self, f.name, arr)
        if n_knots < 3 or n_knots % 2 == 0:
            raise ValueError(f"a Hermite-Simpson trajectory needs an odd number >= 3 of knots, got {n_knots}")

    @property
    def n_knots(self) -> int:
        return self.q.shape[0]

    @property
    def times(self) -> np.ndarray:
        return self.dt * np.arange(self.n_knots)

    @property
    def duration(self) -> float:
        return self.dt * (self.n_knots - 1)

    def point(self, linkage: Linkage, segment: str, point: str) -> np.ndarray:
        """(T, 2) world trajectory of a named segment point."""
        seg = linkage.segment(segment)
        i = linkage.index(segment)
        return np.array([point_position(seg, point, qk[i]) for qk in self.q], dtype=float)

    def signals(self) -> np.ndarray:
        """(T, n) positions, velocities and torques knot by knot: what is observed of a step."""
        t = self.n_knots
        return np.concatenate([self.q.reshape(t, -1), self.v.reshape(t, -1), self.tau], axis=1)

    def to_arrays(self) -> dict[str, np.ndarray]:
        return {f.name: np.asarray(getattr(self, f.name), dtype=float) for f in fields(self)}

    @classmethod
    def from_arrays(cls, arrays: dict[str, np.ndarray]) -> Trajectory:
        return cls(**{f.name: arrays[f.name] for f in fields(cls)})
