"""One benchmark case: an algorithm recovering one weight set under one condition.

``run_case`` makes (or loads) the demonstration, shows the IOC what the condition lets it
see, runs the algorithm, and scores its answer. Whatever the algorithm does (raises,
returns NaN or negative or wrongly sized weights), the case ends in a :class:`CaseResult`
with a status and a reason; it never raises for the algorithm's faults.
"""

from __future__ import annotations

import time
import traceback
from collections.abc import Mapping, Sequence
from dataclasses import asdict, dataclass, field
from typing import Any

import numpy as np

from ioc_bench._version import __version__
from ioc_bench.bench.conditions import Condition, get_condition
from ioc_bench.bench.demos import demonstration
from ioc_bench.bench.observe import observe
from ioc_bench.bench.scoring import unit, weight_error
from ioc_bench.checks import check_seed
from ioc_bench.demo import Demonstration
from ioc_bench.features import COST_FEATURES
from ioc_bench.ioc.algorithm import IOCResult
from ioc_bench.ioc.problem import IOCProblem, OracleSolution
from ioc_bench.ioc.registry import AlgorithmError, check_config, get_algorithm, make_algorithm
from ioc_bench.metrics import trajectory_error
from ioc_bench.model.params import WalkerParams
from ioc_bench.weights import WEIGHT_SETS, WeightSpec, parse_weights

#: Stream of the observation-noise generator (kept apart from the algorithm's streams).
NOISE_STREAM = 7
#: Proximal weight of the first scoring solve (see :func:`regenerate`).
SCORING_PROXIMAL = 30.0


@dataclass(frozen=True)
class CaseResult:
    """The record of one case (what a results file holds).

    Attributes:
        status: the algorithm's status (``converged``, ``max_iterations``, ``infeasible``)
            or ``failed`` (then ``reason`` says why).
        weights: estimated weights over ``features``, unit norm (NaN if failed).
        true_weights: the truth over ``features`` (distractors 0), unit norm.
        weight_error: mean absolute weight difference (SPEC section 5).
        trajectory_error: the paper's trajectory error (segment angles and angular
            velocities, SPEC section 5) of the estimated weights' optimal step, re-solved in
            the observation's basin for scoring.
        found_trajectory_error: the paper's own reading: the trajectory error of the step
            found during the IOC for the output weights (its chosen iteration); None for an
            algorithm without such a step.
        n_solves: forward solves (trajectory optimizations) the algorithm asked for.
        wall_time: seconds the algorithm ran.
        history: per-iteration records as dicts.
        demo_features: every feature of the true demonstration (for Table I); empty when
            the demonstration could not be solved.
        demo_speed: speed of the demonstration.
        family: the algorithm's family (``cutting-plane``, ``inverse-kkt``, ``bilevel``, ...).
    """

    algorithm: str
    weight_set: str
    condition: str
    seed: int
    features: tuple[str, ...]
    status: str
    reason: str
    weights: tuple[float, ...]
    true_weights: tuple[float, ...]
    weight_error: float
    trajectory_error: float
    n_solves: int
    wall_time: float
    history: tuple[dict[str, Any], ...] = ()
    chosen_iteration: int | None = None
    config: dict[str, Any] = field(default_factory=dict)
    oracle: dict[str, Any] = field(default_factory=dict)
    notes: dict[str, Any] = field(default_factory=dict)
    scoring_status: str = ""
    demo_features: dict[str, float] = field(default_factory=dict)
    demo_speed: float = 0.0
    found_trajectory_error: float | None = None
    family: str = ""
    version: str = __version__

    @property
    def failed(self) -> bool:
        return self.status == "failed"

    def to_dict(self) -> dict[str, Any]:
        return asdict(self)

    @classmethod
    def from_dict(cls, data: Mapping[str, Any]) -> CaseResult:
        """Inverse of :meth:`to_dict`, also after a JSON round trip (NaN stored as null)."""
        fields = dict(data)
        for key in ("weights", "true_weights"):
            fields[key] = tuple(_float(v) for v in fields.get(key, ()))
        for key in ("weight_error", "trajectory_error"):
            fields[key] = _float(fields.get(key))
        fields["features"] = tuple(fields.get("features", ()))
        fields["history"] = tuple(fields.get("history", ()))
        return cls(**fields)


def _float(value: Any) -> float:
    return float("nan") if value is None else float(value)


def weight_set_label(weights: WeightSpec) -> str:
    """A set's name, or the numbers joined by commas."""
    if isinstance(weights, str):
        return weights
    return ",".join(f"{float(w):g}" for w in np.asarray(weights, dtype=float).ravel())


def run_case(
    algorithm: str = "log-barrier",
    weights: WeightSpec = "nominal",
    condition: str | Condition = "ideal",
    seed: int = 0,
    config: Mapping[str, Any] | None = None,
    params: WalkerParams | None = None,
    demo: Demonstration | None = None,
) -> CaseResult:
    """Run and score one case.

    Args:
        algorithm: a registered algorithm name (see :func:`ioc_bench.algorithms`).
        weights: the true weights: a set name or numbers over (hip, knee, dtau).
        condition: a condition name (see ``CONDITIONS``) or a :class:`Condition`.
        seed: seed of the algorithm's random choices and of the observation noise.
        config: overrides of the algorithm's config fields.
        params: the true walker model (default: SPEC section 1).
        demo: the true demonstration, if already at hand (else from the cache, or solved).

    Raises:
        ValueError: bad input (unknown algorithm, condition or weight set, a bad config,
            a seed that is not a non-negative integer), before any solve.
    """
    cond = condition if isinstance(condition, Condition) else get_condition(condition)
    true3 = parse_weights(weights)
    seed = check_seed(seed)
    algo = make_algorithm(algorithm, **check_config(config))
    params = params or WalkerParams()
    demo = demo or demonstration(true3, params, cond.demo_task(), seed=seed)
    base = _identity(algorithm, weight_set_label(weights), true3, cond, seed) | {
        "config": algo.config_dict(),
        "demo_features": dict(demo.features),
        "demo_speed": demo.task.speed,
    }
    if not demo.solver.success:
        base["demo_features"] = {}  # a failed demonstration's features describe no optimum
        return _failed(base, f"the demonstration could not be solved ({demo.solver.status})")
    observed = observe(demo.trajectory, cond.noise, np.random.default_rng([seed, NOISE_STREAM]), cond.torques)
    problem = IOCProblem(observed, cond.features, cond.ioc_params(params), cond.ioc_task(), seed=seed)
    t0 = time.perf_counter()
    try:
        result = algo.fit(problem)
    except Exception as exc:  # the algorithm's fault is a recorded result, not a crash
        last = traceback.extract_tb(exc.__traceback__)[-1]
        return _failed(base, f"{type(exc).__name__}: {exc} (at {last.filename}:{last.lineno})", problem, t0)
    wall = time.perf_counter() - t0
    problem_reason = _check_result(result, len(cond.features))
    if problem_reason:
        return _failed(base, problem_reason, problem, t0)
    return _score(base, result, problem, wall)


def failure(
    algorithm: str,
    weights: WeightSpec,
    condition: str,
    seed: int,
    reason: str,
    config: Mapping[str, Any] | None = None,
) -> CaseResult:
    """The record of a case that could not run (e.g. it timed out or its worker died).

    ``config`` is the algorithm's effective config, recorded as ``run_case`` records it.
    """
    cond = get_condition(condition)
    base = _identity(algorithm, weight_set_label(weights), parse_weights(weights), cond, seed)
    return _failed(base | {"config": dict(config or {})}, reason)


def _family(algorithm: str) -> str:
    try:
        return get_algorithm(algorithm).family
    except AlgorithmError:
        return ""


def _identity(algorithm: str, label: str, true3: np.ndarray, cond: Condition, seed: int) -> dict[str, Any]:
    """The fields naming a case and its truth, common to every record."""
    return {
        "algorithm": algorithm,
        "family": _family(algorithm),
        "weight_set": label,
        "condition": cond.name,
        "seed": seed,
        "features": cond.features,
        "true_weights": tuple(unit(_over(true3, cond.features))),
    }


def _over(true3: np.ndarray, features: Sequence[str]) -> np.ndarray:
    """True weights over ``features`` (features outside the cost set get 0)."""
    return np.array([true3[COST_FEATURES.index(f)] if f in COST_FEATURES else 0.0 for f in features])


def _check_result(result: Any, n: int) -> str:
    if not isinstance(result, IOCResult):
        return f"fit() returned {type(result).__name__}, not IOCResult"
    w = np.asarray(result.weights, dtype=float).ravel()
    if w.size != n:
        return f"returned {w.size} weights for {n} features"
    if not np.all(np.isfinite(w)):
        return f"returned non-finite weights {w.tolist()} (status {result.status})"
    if np.any(w < 0):
        return f"returned negative weights {w.tolist()}"
    if not np.any(w > 0):
        return "returned all-zero weights"
    return ""


def regenerate(problem: IOCProblem, weights: np.ndarray) -> OracleSolution:
    """The optimal step for ``weights`` in the observation's basin (for scoring).

    Optima are local, and a plain solve from the observation may wander into another
    basin; so a proximal solve anchored at the observation comes first and an unanchored
    warm-started solve from it then converges to the nearby optimum. A fresh problem
    keeps these solves out of the algorithm's oracle counts.
    """
    scoring = IOCProblem(problem.observed, problem.features, problem.params, problem.task)
    near = scoring.optimize(weights, proximal=SCORING_PROXIMAL)  # from the projected observation
    final = scoring.optimize(weights, start=near) if near.success else near
    return final if final.success else scoring.optimize(weights)


def _score(base: dict, result: IOCResult, problem: IOCProblem, wall: float) -> CaseResult:
    est = unit(np.asarray(result.weights, dtype=float))
    regenerated = regenerate(problem, est)
    traj_err = trajectory_error(regenerated.trajectory, problem.observed) if regenerated.success else float("nan")
    return CaseResult(
        **base,
        status=result.status,
        reason="",
        weights=tuple(float(x) for x in est),
        weight_error=weight_error(est, np.array(base["true_weights"])),
        trajectory_error=traj_err,
        found_trajectory_error=_found(result),
        n_solves=problem.stats.forward_solves,
        wall_time=wall,
        history=tuple(h.to_dict() for h in result.history),
        chosen_iteration=result.chosen_iteration,
        oracle=problem.stats.to_dict(),
        notes=dict(result.notes),
        scoring_status=regenerated.status,
    )


def _found(result: IOCResult) -> float | None:
    """The paper's trajectory error of the step the IOC found for its output (if it has one)."""
    i = result.chosen_iteration
    if i is None or not 0 <= i < len(result.history):
        return None
    error = float(result.history[i].trajectory_error)
    return error if np.isfinite(error) else None


def _failed(base: dict, reason: str, problem: IOCProblem | None = None, t0: float | None = None) -> CaseResult:
    n = len(base["features"])
    return CaseResult(
        **base,
        status="failed",
        reason=reason,
        weights=(float("nan"),) * n,
        weight_error=float("nan"),
        trajectory_error=float("nan"),
        n_solves=problem.stats.forward_solves if problem else 0,
        wall_time=time.perf_counter() - t0 if t0 is not None else 0.0,
        oracle=problem.stats.to_dict() if problem else {},
    )


__all__ = ["WEIGHT_SETS", "CaseResult", "run_case"]
