"""A demonstration: one optimal walking step with everything needed to reuse or check it.

Saved as a single ``.npz`` file: the trajectory arrays, the solver's multipliers (for warm
starts) and a JSON header (schema version, weights, features, model, task, solver report,
multi-start spread). Files are written atomically; loading checks the schema and every
array's shape and names the first problem found.
"""

from __future__ import annotations

import io
import json
import os
import sys
import zipfile
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from ioc_bench.features import COST_FEATURES, available_features, model_features
from ioc_bench.fileio import atomic_write
from ioc_bench.model.catalogue import DEFAULT_MODEL, get_model
from ioc_bench.model.gait_model import GaitModel, GaitParams
from ioc_bench.model.walker import WALKER
from ioc_bench.paths import PathError, check_output_file, read_bytes
from ioc_bench.task import Task
from ioc_bench.trajectory import Trajectory
from ioc_bench.trajopt.gait_figures import GaitFigures
from ioc_bench.trajopt.local_minimum import LocalMinimumCheck
from ioc_bench.trajopt.multistart import MultiStartSummary, StartRecord
from ioc_bench.trajopt.solution import SolverReport
from ioc_bench.validation import MAX_INT, json_fields, load_json, shown

#: Version of the file layout; bump on any incompatible change.
SCHEMA_VERSION = 2
_TRAJ_PREFIX = "traj_"
#: Largest demonstration file read (bytes); ours are well under 1 MB.
MAX_FILE_BYTES = 64 * 2**20
#: Most bytes a demonstration's arrays may unpack to, and most arrays it may hold.
MAX_UNPACKED_BYTES, MAX_MEMBERS = 256 * 2**20, 64


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
        seed: the multi-start's seed (None for a single solve from a given start).
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
    model: str = DEFAULT_MODEL
    gait: GaitFigures | None = None
    local_minimum: LocalMinimumCheck | None = None
    seed: int | None = None

    @property
    def times(self) -> np.ndarray:
        return self.trajectory.times

    @property
    def weight_vector(self) -> np.ndarray:
        """Weights over the cost features (hip, knee, dtau)."""
        return np.array([self.weights.get(f, 0.0) for f in COST_FEATURES])

    def save(self, path: str | os.PathLike) -> Path:
        """Write the demonstration to ``path`` (``.npz``) atomically; returns the path.

        Raises ``ValueError`` (:class:`~ioc_bench.paths.PathError`) for a path that cannot
        be written (see :func:`~ioc_bench.paths.check_output_file`), before writing.
        """
        path = check_output_file(path)
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
            "seed": self.seed,
        }
        arrays = {_TRAJ_PREFIX + k: v for k, v in self.trajectory.to_arrays().items()}
        arrays |= {"lam_x": self.lam_x, "lam_g": self.lam_g, "meta": np.array(json.dumps(meta))}
        atomic_write(path, lambda f: np.savez_compressed(f, **arrays))
        return path

    @classmethod
    def load(cls, path: str | os.PathLike) -> Demonstration:
        """Read a demonstration written by :meth:`save`.

        Raises:
            DemonstrationFileError: for every way the file can be missing, unreadable or
                malformed (a message naming the file and the first problem found): also
                for a ``path`` that is not a path, or names a folder, FIFO or device, or
                a file over :data:`MAX_FILE_BYTES`.
        """
        if isinstance(path, (bytes, bytearray)) or not isinstance(path, (str, os.PathLike)):
            raise DemonstrationFileError(
                f"path must be a demonstration file's path (str or os.PathLike), got {type(path).__name__}"
            )
        try:
            raw = read_bytes(path, MAX_FILE_BYTES, what="demonstration file")
        except PathError as exc:
            raise DemonstrationFileError(str(exc)) from None
        path = Path(path)
        arrays = _read_arrays(path, raw)
        try:
            return cls._from_arrays(arrays)
        except (KeyError, TypeError, ValueError, AttributeError, IndexError, OverflowError) as exc:
            raise DemonstrationFileError(f"{path} is not a valid demonstration: {_one_line(exc)}") from None

    @classmethod
    def _from_arrays(cls, arrays: dict[str, np.ndarray]) -> Demonstration:
        meta = _meta(arrays)
        traj_fields = Trajectory.array_names()
        missing = [n for n in traj_fields if _TRAJ_PREFIX + n not in arrays]
        if missing:
            raise ValueError(f"missing trajectory arrays {missing}")
        for name in traj_fields:
            _numeric(arrays[_TRAJ_PREFIX + name], name, ndim=0 if name == "dt" else None)
        traj = Trajectory.from_arrays({n: arrays[_TRAJ_PREFIX + n] for n in traj_fields})
        model = get_model(meta.get("model", WALKER.name))  # a file from before models were named: the walker's
        params = model.params_from_dict(_object(meta["params"], "params"))
        _check_shapes(traj, model.linkage(params))
        features = _numbers(meta["features"], "features")
        names = _basis_names(model, features)
        weights = _numbers(meta["weights"], "weights")
        if any(w < 0 for w in weights.values()) or set(weights) - set(names):
            raise ValueError(f"weights must be non-negative, over {list(names)}: got {shown(weights)}")
        task = meta["task"]
        if not isinstance(task, dict) or not {"speed"} <= set(task) <= {"speed", "step_length"}:
            raise ValueError(f"task must be an object with a speed (and a step_length), got {shown(task)}")
        n_intervals = meta["n_intervals"]
        if isinstance(n_intervals, bool) or not isinstance(n_intervals, int) or not 0 <= n_intervals <= 10**6:
            raise ValueError(f"n_intervals must be an integer from 0 to 10**6, got {shown(n_intervals)}")
        gait, check, seed = meta.get("gait"), meta.get("local_minimum"), meta.get("seed")
        if seed is not None and (isinstance(seed, bool) or not isinstance(seed, int) or seed < 0):
            raise ValueError(f"seed must be a non-negative integer or null, got {shown(seed)}")
        return cls(
            trajectory=traj,
            weights=weights,
            features=features,
            params=params,
            task=Task(**task),
            solver=_typed(SolverReport, meta["solver"], "solver"),
            multistart=_multistart(meta.get("multistart")),
            n_intervals=n_intervals,
            lam_x=_numeric(arrays.get("lam_x", np.zeros(0)), "lam_x", ndim=1).astype(float),
            lam_g=_numeric(arrays.get("lam_g", np.zeros(0)), "lam_g", ndim=1).astype(float),
            model=model.name,
            gait=None if gait is None else GaitFigures.from_dict(_object(gait, "gait")),
            local_minimum=None if check is None else LocalMinimumCheck.from_dict(_object(check, "local_minimum")),
            seed=seed,
        )


def _basis_names(model: GaitModel, features: dict[str, float]) -> tuple[str, ...]:
    """The features of a file of ``model``, in the model's order: every one of its default
    basis and, for a step solved in a richer cost basis, others it has (``work``,
    ``collision``); ``ValueError`` otherwise."""
    names, available = model_features(model), available_features(model)
    if not set(names) <= set(features) <= set(available):
        raise ValueError(f"features {sorted(features)} do not match {list(names)} (and the model's others)")
    return tuple(f for f in available if f in features)


def _read_arrays(path: Path, raw: bytes) -> dict[str, np.ndarray]:
    """Every array of the ``.npz`` archive ``raw`` read from ``path``, or :class:`DemonstrationFileError`.

    The archive's listing is checked before anything is unpacked: at most
    :data:`MAX_MEMBERS` members of :data:`MAX_UNPACKED_BYTES` in all (no zip bomb).
    """
    if not zipfile.is_zipfile(io.BytesIO(raw)):
        raise DemonstrationFileError(f"{path} is not a readable .npz demonstration (not a zip archive)")
    try:
        with zipfile.ZipFile(io.BytesIO(raw)) as archive:
            members = archive.infolist()
    except Exception as exc:  # a damaged directory fails in zipfile in many ways
        raise DemonstrationFileError(
            f"{path} is not a readable .npz demonstration ({type(exc).__name__}: {_one_line(exc)})"
        ) from None
    unpacked = sum(m.file_size for m in members)
    if len(members) > MAX_MEMBERS or unpacked > MAX_UNPACKED_BYTES:
        raise DemonstrationFileError(
            f"{path} is not a readable .npz demonstration ({len(members)} arrays of {unpacked} bytes unpacked; "
            f"at most {MAX_MEMBERS} of {MAX_UNPACKED_BYTES} bytes)"
        )
    try:
        with np.load(io.BytesIO(raw), allow_pickle=False) as data:
            arrays = {k: data[k] for k in data.files}
    except Exception as exc:  # a damaged archive fails in zipfile, zlib or numpy's format reader
        raise DemonstrationFileError(
            f"{path} is not a readable .npz demonstration ({type(exc).__name__}: {_one_line(exc)})"
        ) from None
    not_arrays = [k for k, v in arrays.items() if not isinstance(v, np.ndarray)]
    if not_arrays:
        raise DemonstrationFileError(f"{path} is not a readable .npz demonstration (members {not_arrays} are not .npy)")
    return arrays


def _meta(arrays: dict[str, np.ndarray]) -> dict:
    if "meta" not in arrays:
        raise ValueError("missing 'meta' header")
    raw = arrays["meta"]
    if raw.shape != () or raw.dtype.kind not in "US":
        raise ValueError(f"'meta' header must be one JSON string, got a {raw.dtype} array of shape {raw.shape}")
    try:
        decoded = load_json(str(raw))
    except ValueError as exc:
        raise ValueError(f"'meta' header is {exc}") from None
    meta = _object(decoded, "'meta' header")
    if meta.get("schema") != SCHEMA_VERSION:
        raise ValueError(f"schema version {meta.get('schema')!r}, this ioc-bench reads {SCHEMA_VERSION}")
    return meta


def _object(value: Any, what: str) -> dict:
    if not isinstance(value, dict):
        raise ValueError(f"{what} must be a JSON object, got {type(value).__name__}")
    return value


def _numbers(value: Any, what: str) -> dict[str, float]:
    """A JSON object of finite numbers, as floats."""
    out = {}
    for key, v in _object(value, what).items():
        if isinstance(v, bool) or not isinstance(v, (int, float)) or not abs(v) <= sys.float_info.max:
            raise ValueError(f"{what}[{shown(key)}] must be a finite number, got {shown(v)}")
        out[key] = float(v)
    return out


def _numeric(arr: np.ndarray, name: str, ndim: int | None = None) -> np.ndarray:
    if arr.dtype.kind not in "iuf":
        raise ValueError(f"array {name} must hold numbers, got dtype {arr.dtype}")
    if (ndim is not None and arr.ndim != ndim) or (ndim is None and arr.ndim == 0):
        raise ValueError(f"array {name} has shape {arr.shape}")
    return arr


def _typed(cls: type, value: Any, what: str) -> Any:
    """A dataclass from a JSON object, every field checked against its annotation."""
    return cls(**json_fields(cls, _object(value, what), what, max_int=MAX_INT))


def _multistart(ms: Any) -> MultiStartSummary | None:
    if ms is None:
        return None
    ms = _object(ms, "multistart")
    starts = ms.get("starts")
    if not isinstance(starts, list):
        raise ValueError("multistart.starts must be a list")
    records = []
    for s in starts:
        s = dict(_object(s, "multistart start"))
        index, origin = s.pop("index", None), s.pop("origin", None)
        if isinstance(index, bool) or not isinstance(index, int) or not isinstance(origin, str):
            raise ValueError("a multistart start needs an integer index and a text origin")
        records.append(StartRecord(index, origin, _typed(SolverReport, s, "multistart start")))
    best = ms.get("best")
    if isinstance(best, bool) or not isinstance(best, int) or not 0 <= best < len(records):
        raise ValueError(f"multistart.best must index its starts, got {shown(best)}")
    return MultiStartSummary(tuple(records), best)


def _one_line(exc: BaseException) -> str:
    return " ".join(str(exc).split())


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
