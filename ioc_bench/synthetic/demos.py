"""Demonstrations for the benchmark, cached on disk by their inputs.

A demonstration is the 15-start optimum for (weights, model, task, seed); it is solved
once and reused by every case and suite that needs it. The cache directory is
:func:`~ioc_bench.cache.cache_dir`; entries are keyed by a hash of the inputs and of
:data:`SOLVER_REVISION`, written atomically, and checked against that key when read.

Logged to ``ioc_bench.synthetic.demos``: a demonstration solved (INFO, with its time), read
from the cache (DEBUG), a cache entry that is not the one asked for or cannot be written
(WARNING).
"""

from __future__ import annotations

import io
import json
import logging
import time
import zipfile
from dataclasses import dataclass
from pathlib import Path
from typing import Any, ClassVar

import numpy as np

from ioc_bench.cache import CachedInput, cache_dir
from ioc_bench.demo import Demonstration, DemonstrationFileError
from ioc_bench.features import cost_features
from ioc_bench.fileio import atomic_write
from ioc_bench.model.catalogue import DEFAULT_MODEL, get_model
from ioc_bench.optimize import DEFAULT_STARTS, optimize_gait
from ioc_bench.paths import read_bytes
from ioc_bench.task import Task
from ioc_bench.trajopt.solution import SolverReport, StartPoint
from ioc_bench.trajopt.step_problem import DEFAULT_INTERVALS

#: Bump whenever the transcription or solver settings change the optima.
SOLVER_REVISION = 6
#: Multi-start seed of a demonstration made outside a case (a case uses its own seed, so
#: seeds vary the demonstration as a new experiment would).
DEMO_SEED = 0

logger = logging.getLogger(__name__)


@dataclass(frozen=True, eq=False)
class DemoRequest(CachedInput):
    """What makes a demonstration: the one key for the cache and for sharing it between cases.

    Attributes:
        weights: unit weights over the model's features (its cost features for a case).
        params: the model's parameters.
        task: the task.
        seed: the multi-start seed.
        model: the gait model's name.
        starts: multi-start size.
        n_intervals: Hermite-Simpson intervals.
        features: the forward problem's basis ``weights`` are over (None: the model's
            default basis, :func:`~ioc_bench.features.model_features`).
    """

    weights: np.ndarray
    params: Any
    task: Task
    seed: int = DEMO_SEED
    model: str = DEFAULT_MODEL
    starts: int = DEFAULT_STARTS
    n_intervals: int = DEFAULT_INTERVALS
    features: tuple[str, ...] | None = None

    revision: ClassVar[int] = SOLVER_REVISION

    def payload(self) -> dict[str, Any]:
        """Every input of the demonstration (the default model is not named in it)."""
        payload = {
            "weights": [round(float(w), 12) for w in self.weights],
            "params": self.params.to_dict(),
            "speed": self.task.speed,
            "seed": self.seed,
            "starts": self.starts,
            "n_intervals": self.n_intervals,
        }
        if self.task.step_length is not None:
            payload["step_length"] = self.task.step_length
        if self.model != DEFAULT_MODEL:
            payload["model"] = self.model
        if self.features is not None:
            payload["features"] = list(self.features)
        return payload

    def prepare(self) -> Demonstration:
        """The demonstration: from the cache if its entry is this request's, else solved (all cores)."""
        return demonstration(self)

    def solve(self, workers: int | None = None) -> Demonstration:
        return optimize_gait(
            self.weights,
            self.params,
            self.task,
            starts=self.starts,
            seed=self.seed,
            n_intervals=self.n_intervals,
            workers=workers,
            model=get_model(self.model),
            features=self.features,
        )


def demonstration(
    weights: np.ndarray | DemoRequest,
    params: Any = None,
    task: Task | None = None,
    seed: int = DEMO_SEED,
    starts: int = DEFAULT_STARTS,
    n_intervals: int = DEFAULT_INTERVALS,
    workers: int | None = None,
    use_cache: bool = True,
) -> Demonstration:
    """The optimal step of a :class:`DemoRequest` (or, for the walker, of unit ``weights``
    over (hip, knee, dtau) and the other arguments), from the cache if there."""
    if isinstance(weights, DemoRequest):
        request = weights
    else:
        from ioc_bench.model.params import WalkerParams
        from ioc_bench.model.walker import WALKER

        request = DemoRequest(weights, params or WalkerParams(), task or Task(), seed, WALKER.name, starts, n_intervals)
    path = cache_dir() / "demos" / f"{request.key}.npz"
    if use_cache and path.is_file():
        try:
            demo = Demonstration.load(path)
            wrong = mismatch(request, demo)
        except DemonstrationFileError as exc:  # a stale or broken entry: solved again and replaced
            wrong = str(exc)
        if not wrong:
            logger.debug("demonstration %s read from the cache", request.key)
            return demo
        logger.warning("cache entry %s cannot be used (%s); solving the demonstration again", path, wrong)
    logger.info(
        "solving demonstration %s: %s weights %s at speed %g, %d start(s), seed %d",
        request.key,
        request.model,
        np.round(request.weights, 4).tolist(),
        request.task.speed,
        request.starts,
        request.seed,
    )
    t0 = time.perf_counter()
    demo = request.solve(workers)
    logger.info("demonstration %s solved in %.1f s", request.key, time.perf_counter() - t0)
    if use_cache:
        try:
            demo.save(path)
        except (OSError, ValueError) as exc:  # a demonstration that cannot be kept is only solved again
            logger.warning("could not keep demonstration %s in the cache: %s", request.key, exc)
    return demo


def mismatch(request: DemoRequest, demo: Demonstration) -> str:
    """Why ``demo`` is not the demonstration ``request`` asks for ("" if it is): a cache entry
    is trusted only once its content is the key it is filed under."""
    cost = cost_features(get_model(request.model))
    weights = np.array([demo.weights.get(f, 0.0) for f in cost])
    norm = np.linalg.norm(weights)
    checks = [
        (demo.model == request.model, f"model {demo.model!r}"),
        (norm > 0 and np.allclose(weights / norm, request.weights, atol=1e-9), f"weights {dict(demo.weights)}"),
        (demo.params.to_dict() == request.params.to_dict(), "other model parameters"),
        (demo.task == request.task, f"task {demo.task}"),
        (demo.seed == request.seed, f"multi-start seed {demo.seed}"),
        (demo.n_intervals == request.n_intervals, f"{demo.n_intervals} intervals"),
        (demo.multistart is not None and len(demo.multistart.starts) == request.starts, "another multi-start size"),
    ]
    return next((what for ok, what in checks if not ok), "")


#: Largest reference file read back (a walker's is about 50 kB).
MAX_REFERENCE_BYTES = 10_000_000


class ReferenceCache:
    """The feasible references of observations, kept on disk beside the demonstrations.

    Every algorithm of a suite, and the scoring of every case, start from the reference of
    the same observation (its projection, smoothed for a noisy one: up to five solves).
    Kept under ``<cache>/references/<key>.npz`` (the key hashes the observation, model,
    parameters and task, and :data:`SOLVER_REVISION`), written atomically, with the key
    inside: an unreadable entry, or one whose recorded key is not its name's (a file of
    another observation copied over it), is treated as absent, so it is computed again and
    replaced.
    """

    def __init__(self, root: Path | None = None):
        self.root = (root or cache_dir()) / "references"

    def _path(self, key: str) -> Path:
        return self.root / f"{key}-r{SOLVER_REVISION}.npz"

    def get(self, key: str) -> tuple[StartPoint, SolverReport, int, float] | None:
        path = self._path(key)
        if not path.is_file():
            return None
        try:
            with np.load(io.BytesIO(read_bytes(path, MAX_REFERENCE_BYTES, "reference")), allow_pickle=False) as f:
                arrays = {k: f[k] for k in ("key", "x", "lam_x", "lam_g", "report", "solves", "seconds")}
            if str(arrays["key"]) != key:
                return None
            report = SolverReport(**json.loads(str(arrays["report"])))
            point = StartPoint(*(np.asarray(arrays[k], dtype=float) for k in ("x", "lam_x", "lam_g")))
            return point, report, int(arrays["solves"]), float(arrays["seconds"])
        except (OSError, ValueError, KeyError, TypeError, zipfile.BadZipFile):
            return None

    def put(self, key: str, point: StartPoint, report: SolverReport, solves: int, seconds: float) -> None:
        def write(f) -> None:
            np.savez(
                f,
                key=np.array(key),
                x=point.x,
                lam_x=point.lam_x,
                lam_g=point.lam_g,
                report=np.array(json.dumps(report.to_dict())),
                solves=np.array(solves),
                seconds=np.array(seconds),
            )

        try:
            atomic_write(self._path(key), write)
        except (OSError, ValueError) as exc:  # a reference that cannot be kept is only recomputed
            logger.warning("could not keep reference %s in the cache: %s", key, exc)
