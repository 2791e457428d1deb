"""A demonstration: one optimal walking step with everything needed to reuse or check it.

Saved as a single ``.npz`` file: the trajectory arrays, the solver's multipliers (for warm
starts) and a JSON header (schema version, weights, features, model, task, solver report,
multi-start spread). Files are written atomically; loading checks the schema and every
array's shape and names the first problem found.
"""

from __future__ import annotations

import json
import os
import zipfile
from dataclasses import dataclass, field, fields
from pathlib import Path

import numpy as np

from ioc_bench.features import COST_FEATURES, model_features
from ioc_bench.fileio import atomic_write
from ioc_bench.model.catalogue import get_model
from ioc_bench.model.gait_model import GaitParams
from ioc_bench.task import Task
from ioc_bench.trajectory import Trajectory
from ioc_bench.trajopt.gait_figures import GaitFigures
from ioc_bench.trajopt.local_minimum import LocalMinimumCheck
from ioc_bench.trajopt.multistart import MultiStartSummary, StartRecord
from ioc_bench.trajopt.solver import SolverReport

#: Version of the file layout; bump on any incompatible change.
SCHEMA_VERSION = 2
_TRAJ_PREFIX = "traj_"


class DemonstrationFileError(ValueError):
    """A demonstration file is missing, unreadable or malformed."""


@dataclass(frozen=True, eq=False)
class Demonstration:
    """One optimal step of the walker for given cost weights.

    Attributes:
        trajectory: the step (knot times, segment states, torques, pin forces, impulses).
        weights: unit-norm weights that generated it, by feature name (distractors 0).
        features: every feature's value on the step, by name.
        params: the walker model it was optimized for.
        task: the task (speed) it achieves.
        solver: report of the solve that produced it.
        multistart: the spread of optima over all starts (None for a single solve).
        n_intervals: Hermite-Simpson intervals of the transcription.
        lam_x, lam_g: IPOPT multipliers at the solution, for warm starts (may be empty).
        model: name of the gait model (see ``ioc_bench.model.catalogue``).
        gait: step length, duration, cadence, clearance, peak torques, active bounds.
        local_minimum: the check that no proximal descent under its own weights finds a
            cheaper step (None if not checked, e.g. for an infeasible solve).
    """

    trajectory: Trajectory
    weights: dict[str, float]
    features: dict[str, float]
    params: GaitParams
    task: Task
    solver: SolverReport
    multistart: MultiStartSummary | None = None
    n_intervals: int = 0
    lam_x: np.ndarray = field(default_factory=lambda: np.zeros(0))
    lam_g: np.ndarray = field(default_factory=lambda: np.zeros(0))
    model: str = "walker"
    gait: GaitFigures | None = None
    local_minimum: LocalMinimumCheck | None = None

    @property
    def times(self) -> np.ndarray:
        return self.trajectory.times

    @property
    def weight_vector(self) -> np.ndarray:
        """Weights over the cost features (hip, knee, dtau)."""
        return np.array([self.weights.get(f, 0.0) for f in COST_FEATURES])

    def save(self, path: str | os.PathLike) -> Path:
        """Write the demonstration to ``path`` (``.npz``) atomically; returns the path."""
        path = Path(path)
        meta = {
            "schema": SCHEMA_VERSION,
            "weights": self.weights,
            "features": self.features,
            "params": self.params.to_dict(),
            "task": self.task.to_dict(),
            "solver": self.solver.to_dict(),
            "multistart": None
            if self.multistart is None
            else {"best": self.multistart.best, "starts": [s.to_dict() for s in self.multistart.starts]},
            "n_intervals": self.n_intervals,
            "model": self.model,
            "gait": None if self.gait is None else self.gait.to_dict(),
            "local_minimum": None if self.local_minimum is None else self.local_minimum.to_dict(),
        }
        arrays = {_TRAJ_PREFIX + k: v for k, v in self.trajectory.to_arrays().items()}
        arrays |= {"lam_x": self.lam_x, "lam_g": self.lam_g, "meta": np.array(json.dumps(meta))}
        atomic_write(path, lambda f: np.savez_compressed(f, **arrays))
        return path

    @classmethod
    def load(cls, path: str | os.PathLike) -> Demonstration:
        """Read a demonstration; raises :class:`DemonstrationFileError` naming the problem."""
        path = Path(path)
        if not path.is_file():
            raise DemonstrationFileError(f"demonstration file not found: {path}")
        try:
            with np.load(path, allow_pickle=False) as data:
                arrays = {k: data[k] for k in data.files}
        except (OSError, ValueError, zipfile.BadZipFile, EOFError) as exc:
            raise DemonstrationFileError(f"{path} is not a readable .npz demonstration ({exc})") from None
        try:
            return cls._from_arrays(arrays)
        except (KeyError, TypeError, ValueError) as exc:
            raise DemonstrationFileError(f"{path} is not a valid demonstration: {exc}") from None

    @classmethod
    def _from_arrays(cls, arrays: dict[str, np.ndarray]) -> Demonstration:
        if "meta" not in arrays:
            raise ValueError("missing 'meta' header")
        meta = json.loads(str(arrays["meta"]))
        if meta.get("schema") != SCHEMA_VERSION:
            raise ValueError(f"schema version {meta.get('schema')!r}, this ioc-bench reads {SCHEMA_VERSION}")
        traj_fields = [f.name for f in fields(Trajectory)]
        missing = [n for n in traj_fields if _TRAJ_PREFIX + n not in arrays]
        if missing:
            raise ValueError(f"missing trajectory arrays {missing}")
        traj = Trajectory.from_arrays({n: arrays[_TRAJ_PREFIX + n] for n in traj_fields})
        model = get_model(meta.get("model", "walker"))
        params = model.params_from_dict(meta["params"])
        _check_shapes(traj, model.linkage(params))
        ms = meta.get("multistart")
        summary = None
        if ms is not None:
            summary = MultiStartSummary(tuple(StartRecord.from_dict(s) for s in ms["starts"]), int(ms["best"]))
        features = {k: float(v) for k, v in meta["features"].items()}
        if set(features) != set(model_features(model)):
            raise ValueError(f"features {sorted(features)} do not match {list(model_features(model))}")
        gait, check = meta.get("gait"), meta.get("local_minimum")
        return cls(
            trajectory=traj,
            weights={k: float(v) for k, v in meta["weights"].items()},
            features=features,
            params=params,
            task=Task(**meta["task"]),
            solver=SolverReport(**meta["solver"]),
            multistart=summary,
            n_intervals=int(meta["n_intervals"]),
            lam_x=np.asarray(arrays.get("lam_x", np.zeros(0)), dtype=float),
            lam_g=np.asarray(arrays.get("lam_g", np.zeros(0)), dtype=float),
            model=model.name,
            gait=None if gait is None else GaitFigures.from_dict(gait),
            local_minimum=None if check is None else LocalMinimumCheck.from_dict(check),
        )


def _check_shapes(traj: Trajectory, linkage) -> None:
    t, s, a = traj.n_knots, len(linkage.segments), len(linkage.actuated)
    lk, p = len(linkage.locked), len(linkage.pins)
    expected = {
        "q": (t, s, 3),
        "v": (t, s, 3),
        "acc": (t, s, 3),
        "tau": (t, a),
        "lock": (t, lk),
        "pin_forces": (t, p, 2),
        "impulses": (p, 2),
        "trail_impulse": (2,),
        "lock_impulses": (lk,),
    }
    for name, shape in expected.items():
        if getattr(traj, name).shape != shape:
            raise ValueError(f"array {name} has shape {getattr(traj, name).shape}, expected {shape}")
