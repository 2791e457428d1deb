"""One benchmark case: an algorithm recovering one weight set of one model under one condition.

A :class:`CaseSpec` names a case and is resolved once, when made: its model, its true
weights, its features, its condition and its config are checked and kept, and every layer
below reads them from it. :func:`run_case` (the Python API and ``ioc-bench ioc``) and the
suite runner (``ioc-bench run``) both go through :func:`run_spec`, handing it the algorithm
built once for the case: make (or load) the demonstration, show the IOC what the condition
lets it see, run the algorithm, check what it returned at the boundary
(:mod:`ioc_bench.ioc.contract`) and score it on the case's own problem. Whatever the
algorithm does (raises, returns something the contract does not allow), the case ends in a
:class:`CaseResult` with a status, a reason, and the time and forward solves it spent; it
never raises for the algorithm's faults.
"""

from __future__ import annotations

import hashlib
import json
import os
import time
from collections.abc import Mapping, Sequence
from dataclasses import asdict, dataclass, field, fields, replace
from pathlib import Path
from typing import Any

import numpy as np

from ioc_bench._version import __version__
from ioc_bench.bases import DEFAULT_BASIS, forward_basis, get_basis, parse_basis_weights
from ioc_bench.cache import check_cache
from ioc_bench.demo import Demonstration
from ioc_bench.ioc.algorithm import IOCAlgorithm, IOCResult
from ioc_bench.ioc.fit import Fit, fit
from ioc_bench.ioc.oracle import OracleSolution
from ioc_bench.ioc.problem import IOCProblem, MultiTrialProblem
from ioc_bench.ioc.registry import (
    AlgorithmError,
    canonical_config,
    check_algorithm_name,
    check_config,
    get_algorithm,
    make_algorithm,
)
from ioc_bench.metrics import trajectory_error
from ioc_bench.model.catalogue import DEFAULT_MODEL, resolve_model
from ioc_bench.model.gait_model import GaitModel, GaitParams
from ioc_bench.provenance import provenance
from ioc_bench.synthetic.conditions import Condition, get_condition
from ioc_bench.synthetic.demos import DemoRequest, ReferenceCache, demonstration
from ioc_bench.synthetic.observe import observe
from ioc_bench.synthetic.scoring import unit, weight_error
from ioc_bench.synthetic.transfer import transfer, transfer_task
from ioc_bench.validation import check_seed
from ioc_bench.weights import WEIGHT_SETS, WeightSpec, full_weights, parse_weights

#: Stream of the observation-noise generator (kept apart from the algorithm's streams).
NOISE_STREAM = 7
#: Proximal weight of the first scoring solve (see :func:`regenerate`).
SCORING_PROXIMAL = 30.0


@dataclass(frozen=True)
class CaseSpec:
    """What identifies a case, resolved and checked once, when made.

    The model (a name, or the catalogue's model itself) is resolved once and kept beside its
    name, as the condition is; the case's cost features and features are computed once.
    Raises ``ValueError`` (one line) for an unsafe algorithm name, an unknown model, weight
    set or condition, a condition whose features the model lacks, a seed that is not a
    non-negative integer, or a bad config; ``config`` is stored in canonical form (which
    needs the algorithm to be registered, unless it is empty).

    Attributes:
        algorithm: the algorithm's registered name.
        weight_set: the true weights: a set name of the model, or ``"hip,knee,dtau"`` numbers.
        condition: the condition's name (a :class:`Condition` is accepted and kept).
        seed: the case's seed (demonstration multi-start, observation noise, algorithm).
        config: the algorithm's config overrides (canonical: fields that differ from defaults).
        model: the gait model's name (the model itself is accepted and kept: :attr:`gait_model`).
        basis: the cost basis the true weights are over and the IOC weighs
            (:data:`~ioc_bench.bases.COST_BASES`; its features after the condition's).
    """

    algorithm: str
    weight_set: str
    condition: str
    seed: int
    config: Mapping[str, Any] = field(default_factory=dict)
    model: str = DEFAULT_MODEL
    basis: str = DEFAULT_BASIS
    #: (C,) unit true weights over the basis's features, parsed once from ``weight_set``.
    true_weights: np.ndarray = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        check_algorithm_name(self.algorithm)
        cond = self.condition if isinstance(self.condition, Condition) else get_condition(self.condition)
        object.__setattr__(self, "condition", cond.name)
        object.__setattr__(self, "_condition", cond)
        if not isinstance(self.model, (str, GaitModel)):
            raise ValueError(f"a case's model is a model name, got {type(self.model).__name__}")
        gait_model = resolve_model(self.model)
        object.__setattr__(self, "model", gait_model.name)
        object.__setattr__(self, "_model", gait_model)
        if not isinstance(self.weight_set, str):
            raise ValueError(f"a case's weight set is a name or 'hip,knee,dtau' text, got {self.weight_set!r}")
        cost = get_basis(self.basis).features(gait_model)
        object.__setattr__(self, "_cost_features", cost)
        object.__setattr__(self, "true_weights", parse_basis_weights(self.weight_set, cost))
        object.__setattr__(self, "_features", cond.features_for(gait_model, cost))
        object.__setattr__(self, "_demo_basis", forward_basis(gait_model, cost))
        if not any(f in cost for f in self.features):
            raise ValueError(f"condition {cond.name!r} offers model {self.model!r} none of its cost features")
        object.__setattr__(self, "seed", check_seed(self.seed))
        config = check_config(self.config)
        object.__setattr__(self, "config", canonical_config(self.algorithm, config) if config else {})

    @property
    def condition_def(self) -> Condition:
        """The condition itself."""
        return self._condition  # type: ignore[attr-defined]

    @property
    def gait_model(self) -> GaitModel:
        """The model itself."""
        return self._model  # type: ignore[attr-defined]

    @property
    def cost_features(self) -> tuple[str, ...]:
        """The features the true weights are over: the case's basis on its model."""
        return self._cost_features  # type: ignore[attr-defined]

    @property
    def features(self) -> tuple[str, ...]:
        """The features the IOC may weigh in this case: the condition's, then the basis's others."""
        return self._features  # type: ignore[attr-defined]

    @property
    def demo_basis(self) -> tuple[str, ...] | None:
        """The basis the demonstrations are solved in (None: the model's default)."""
        return self._demo_basis  # type: ignore[attr-defined]

    def make_algorithm(self) -> IOCAlgorithm:
        """The case's algorithm with its config (build it once per case and pass it down)."""
        return make_algorithm(self.algorithm, **self.config)

    def true_over_features(self) -> np.ndarray:
        """The unit true weights over :attr:`features` (features outside the cost set get 0)."""
        cost = self.cost_features
        return unit(np.array([self.true_weights[cost.index(f)] if f in cost else 0.0 for f in self.features]))

    def demo_request(self, params: GaitParams | None = None) -> DemoRequest:
        """The demonstration this case observes (its first trial's; its multi-start seed is the
        case's seed)."""
        return self.demo_requests(params)[0]

    def demo_requests(self, params: GaitParams | None = None) -> list[DemoRequest]:
        """The demonstration of every trial this case observes (one, unless multi-trial)."""
        params = self.gait_model.default_params if params is None else params
        cond = self.condition_def
        return [
            DemoRequest(
                self.true_weights_over(self.demo_basis),
                params,
                cond.demo_task(k),
                self.seed,
                self.model,
                features=self.demo_basis,
            )
            for k in range(len(cond.speeds))
        ]

    def transfer_request(self, params: GaitParams | None = None) -> DemoRequest | None:
        """The true weights' demonstration at the speed this case's cost is tested at
        (:mod:`ioc_bench.synthetic.transfer`), or None if its speed has no counterpart (or the
        case observes several speeds already)."""
        task = transfer_task(self.condition_def.demo_speed)
        if task is None or len(self.condition_def.speeds) > 1:
            return None
        params = self.gait_model.default_params if params is None else params
        basis = self.demo_basis
        return DemoRequest(self.true_weights_over(basis), params, task, self.seed, self.model, features=basis)

    def true_weights_over(self, basis: Sequence[str] | None) -> np.ndarray:
        """The true weights as a demonstration request takes them: over the cost features for
        the default basis (None), else over ``basis`` (the others 0)."""
        if basis is None:
            return self.true_weights
        return full_weights(self.true_weights, self.cost_features, basis)

    # -- the case protocol (:mod:`ioc_bench.runner.protocol`) ---------------------------------------
    track = "synthetic"

    @classmethod
    def identity_fields(cls) -> tuple[str, ...]:
        """The fields that name a case: a result file's name and content agree on each."""
        return tuple(f.name for f in fields(cls) if f.init)

    def needs(self) -> list[DemoRequest]:
        """The demonstrations the case needs: every trial's and, if it has one, the one its cost
        is tested at (prepared once by the runner for every case that shares them)."""
        other = self.transfer_request()
        return self.demo_requests() + ([other] if other is not None else [])

    def run(self, inputs: Mapping[DemoRequest, Demonstration]) -> CaseResult:
        """Run and score the case (in a worker) on the prepared demonstrations."""
        first, *others = (inputs[r] for r in self.demo_requests())
        other = self.transfer_request()
        return run_spec(self, demo=first, transfer_demo=None if other is None else inputs[other], trial_demos=others)

    def failure(self, reason: str, config: Mapping[str, Any] | None = None) -> CaseResult:
        """The record of the case when it could not run (it timed out, its worker died)."""
        return failure(self, reason, config)

    def write_extras(self, root: str | os.PathLike, record: CaseResult) -> None:
        """Nothing: a synthetic case's figures come from ``ioc-bench figures``."""

    @property
    def key(self) -> str:
        """Relative path of the case's result file, without suffix."""
        name = f"{_safe(self.weight_set)}__{self.condition}__seed{self.seed}"
        if self.model != DEFAULT_MODEL:
            name += f"__model-{self.model}"
        if self.basis != DEFAULT_BASIS:
            name += f"__basis-{self.basis}"
        if self.config:
            name += f"__cfg{config_digest(self.config)}"
        return f"{self.algorithm}/{name}"

    def path(self, root: str | os.PathLike) -> Path:
        return Path(root) / f"{self.key}.json"


def config_digest(config: Mapping[str, Any]) -> str:
    """Eight hex digits naming a canonical config (in file names and leaderboards)."""
    return hashlib.sha256(json.dumps(dict(config), sort_keys=True).encode()).hexdigest()[:8]


def _safe(text: str) -> str:
    return "".join(c if c.isalnum() or c in "-._" else "_" for c in text)


@dataclass(frozen=True)
class CaseResult:
    """The record of one case (what a results file holds).

    Attributes:
        status: the algorithm's status (``converged``, ``max_iterations``, ``infeasible``)
            or ``failed`` (then ``reason`` says why).
        weights: estimated weights over ``features``, unit norm (NaN if failed).
        true_weights: the truth over ``features`` (distractors 0), unit norm.
        weight_error: mean absolute weight difference (``docs/spec.md``, "Metrics").
        trajectory_error: the paper's trajectory error (segment angles and angular
            velocities, ``docs/spec.md``, "Metrics") of the estimated weights' optimal step, re-solved in
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
        model: the gait model.
        basis: the cost basis of the true weights (a record without one: the effort basis).
        uncertainty: the algorithm's region for the weights (:class:`WeightRegion` as a
            dict), None if it reports none.
        covered: whether that region holds the true weights (None without a region).
        transfer: the estimated weights' optimum at the other speed against the true one
            there (:class:`~ioc_bench.synthetic.transfer.Transfer` as a dict), None if the case
            has no other speed or failed.
        scoring_time: seconds spent scoring after the algorithm (re-solving its weights'
            step, the transfer solve), not counted in ``wall_time``.
        model_fit: the algorithm's test of whether its model fits the observation
            (:class:`~ioc_bench.ioc.algorithm.ModelFit` as a dict), None if it reports none;
            when ``model_fit["rejected"]`` the region is conditional on a model the data reject.
        version: the ioc-bench version that ran the case.
        provenance: the commit and package versions the case ran with
            (:func:`ioc_bench.provenance.provenance`, taken in the process that ran it);
            ``{}`` in a record made before it was recorded.
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
    model: str = DEFAULT_MODEL
    uncertainty: dict[str, Any] | None = None
    covered: bool | None = None
    transfer: dict[str, Any] | None = None
    scoring_time: float = 0.0
    model_fit: dict[str, Any] | None = None
    basis: str = DEFAULT_BASIS
    version: str = __version__
    provenance: dict[str, Any] = field(default_factory=dict)

    @property
    def failed(self) -> bool:
        return self.status == "failed"

    def headline(self) -> str:
        """The case's outcome in a few words (for progress lines)."""
        return f"FAILED ({self.reason})" if self.failed else f"weight error {self.weight_error:.4f}"

    @property
    def misfit(self) -> bool | None:
        """Whether the data reject the algorithm's model (None without a test)."""
        return None if self.model_fit is None else bool(self.model_fit["rejected"])

    def to_dict(self) -> dict[str, Any]:
        return asdict(self)


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
    params: GaitParams | None = None,
    demo: Demonstration | None = None,
    *,
    model: str | GaitModel = DEFAULT_MODEL,
    basis: str = DEFAULT_BASIS,
) -> CaseResult:
    """Run and score one case.

    Args:
        algorithm: a registered algorithm name (see :func:`ioc_bench.algorithms`).
        weights: the true weights: a set name of the model or numbers over its cost features.
        condition: a condition name (see ``CONDITIONS``) or a :class:`Condition`.
        seed: seed of the algorithm's random choices and of the observation noise.
        config: overrides of the algorithm's config fields.
        params: the true model parameters (default: the model's, or ``demo``'s).
        demo: the true demonstration, if already at hand (else from the cache, or solved);
            it must be the case's (its weights, speed and model), or ``ValueError``.
        model: the gait model, by name or object (keyword only; default the walker).
        basis: the cost basis of the true weights and of the IOC (keyword only; default
            the effort basis, :data:`~ioc_bench.bases.COST_BASES`).

    Raises:
        ValueError: bad input (unknown algorithm, model, condition or weight set, a bad
            config, a seed that is not a non-negative integer, a demonstration of another
            case), before any solve.
    """
    if isinstance(model, (str, GaitModel)):
        model = resolve_model(model)  # once: the spec keeps it (anything else the spec refuses)
    if not isinstance(weights, str):
        features = get_basis(basis).features(model)
        weights = weight_set_label(parse_weights(weights, features) if _is_mapping(weights) else weights)
    spec = CaseSpec(algorithm, weights, condition, check_seed(seed), check_config(config), model, basis)
    algo = spec.make_algorithm()  # the name and every config field, before any work; built once
    return run_spec(spec, params, demo, algo=algo)


def _is_mapping(value: Any) -> bool:
    return isinstance(value, Mapping)


def run_spec(
    spec: CaseSpec,
    params: GaitParams | None = None,
    demo: Demonstration | None = None,
    transfer_demo: Demonstration | None = None,
    trial_demos: Sequence[Demonstration] = (),
    *,
    algo: IOCAlgorithm | None = None,
) -> CaseResult:
    """Run and score the case ``spec`` (see :func:`run_case`; the runner's entry point, which
    hands over the demonstrations it prepared: the observed one, the other trials' of a
    multi-trial case, and the transfer speed's).

    ``algo`` is the case's algorithm if the caller built it already (``spec.make_algorithm()``:
    built once per case, then used for the record's config and the fit); None builds it here.
    """
    algo = _case_algorithm(spec, algo)
    params = _params(spec, params, demo)
    requests = spec.demo_requests(params)
    given = [demo, *trial_demos] if demo is not None else list(trial_demos)
    if len(given) < len(requests) or (spec.transfer_request(params) is not None and transfer_demo is None):
        check_cache()  # demonstrations will be read or saved there: refuse an unusable cache before any solve
    demos = [given[k] if k < len(given) else demonstration(r) for k, r in enumerate(requests)]
    for request, d in zip(requests, given):
        _check_demo(spec, request, d)
    other = spec.transfer_request(params)
    if other is not None and transfer_demo is not None:
        _check_demo(spec, other, transfer_demo)
    base = _identity(spec) | {
        "config": algo.config_dict(),
        "demo_features": dict(demos[0].features),
        "demo_speed": demos[0].task.speed,
    }
    unsolved = [d for d in demos if not d.solver.success]
    if unsolved:
        base["demo_features"] = {}  # a failed demonstration's features describe no optimum
        return _failed(base, f"the demonstration could not be solved ({unsolved[0].solver.status})")
    problem = _problem(spec, params, demos)
    outcome = fit(algo, problem)
    if outcome.failed:
        return _failed(base, outcome.reason, outcome)
    truth = None if other is None else (transfer_demo if transfer_demo is not None else demonstration(other))
    t1 = time.perf_counter()
    scored = _score(base, outcome, problem)
    if truth is not None and not truth.solver.success:
        scored = replace(scored, transfer={"speed": other.task.speed, "status": "no demonstration"})
    elif truth is not None:
        moved = transfer(np.array(scored.weights), spec.features, truth, model=spec.gait_model)
        scored = replace(scored, transfer=moved.to_dict())
    return replace(scored, scoring_time=time.perf_counter() - t1)


def _case_algorithm(spec: CaseSpec, algo: IOCAlgorithm | None) -> IOCAlgorithm:
    """``algo``, if it is the case's algorithm (else ``ValueError``), or the case's built now."""
    if algo is None:
        return spec.make_algorithm()
    if not isinstance(algo, IOCAlgorithm) or algo.name != spec.algorithm:
        given = getattr(algo, "name", "") or type(algo).__name__
        raise ValueError(f"the algorithm given ({given}) is not the case's, {spec.algorithm!r}")
    return algo


def _problem(spec: CaseSpec, params: GaitParams, demos: Sequence[Demonstration]) -> IOCProblem | MultiTrialProblem:
    """What the IOC sees of the case's demonstrations: one problem per trial (the first trial's
    noise is drawn as a single-trial case's, so a multi-trial case extends it)."""
    cond = spec.condition_def
    trials = []
    for k, d in enumerate(demos):
        rng = np.random.default_rng([spec.seed, NOISE_STREAM] + ([k] if k else []))
        observed = observe(d.trajectory, cond.noise, rng, cond.torques)
        ioc_params, task = cond.ioc_params(params), cond.ioc_task(k)
        trials.append(
            IOCProblem(
                observed,
                spec.features,
                ioc_params,
                task,
                seed=spec.seed,
                model=spec.gait_model,
                reference_store=ReferenceCache(),
            )
        )
    return trials[0] if len(trials) == 1 else MultiTrialProblem(trials)


def _params(spec: CaseSpec, params: GaitParams | None, demo: Demonstration | None) -> GaitParams:
    kind = type(spec.gait_model.default_params)
    if params is not None and not isinstance(params, kind):
        raise ValueError(f"params must be {kind.__name__} for model {spec.model!r}, got {type(params).__name__}")
    if demo is not None and not isinstance(demo, Demonstration):
        raise ValueError(f"demo must be a Demonstration, got {type(demo).__name__}")
    if params is None:
        return demo.params if demo is not None and isinstance(demo.params, kind) else spec.gait_model.default_params
    return params


def _check_demo(spec: CaseSpec, request: DemoRequest, demo: Demonstration) -> None:
    """Refuse a demonstration that is not this case's (else it would be scored against the wrong truth)."""
    if demo.model != spec.model:
        raise ValueError(f"demo is of model {demo.model!r}, the case's model is {spec.model!r}")
    cost = spec.cost_features
    given = unit(np.array([demo.weights.get(f, 0.0) for f in cost]))
    if not np.allclose(given, spec.true_weights, atol=1e-9) or any(
        demo.weights.get(f, 0.0) for f in demo.weights if f not in cost
    ):
        raise ValueError(f"demo was made with weights {dict(demo.weights)}, not the case's {spec.weight_set!r}")
    if not np.isclose(demo.task.speed, request.task.speed):
        raise ValueError(
            f"demo walks at speed {demo.task.speed}, the case's condition demonstrates {request.task.speed}"
        )
    if demo.params.to_dict() != request.params.to_dict():
        raise ValueError("demo was made with other model parameters than the case's")


def failure(spec: CaseSpec, reason: str, config: Mapping[str, Any] | None = None) -> CaseResult:
    """The record of a case that could not run (e.g. it timed out or its worker died).

    ``config`` is the algorithm's effective config, recorded as ``run_case`` records it.
    """
    return _failed(_identity(spec) | {"config": dict(config or {})}, reason)


def _family(algorithm: str) -> str:
    try:
        return get_algorithm(algorithm).family
    except AlgorithmError:
        return ""


def _identity(spec: CaseSpec) -> dict[str, Any]:
    """The fields naming a case and its truth, common to every record."""
    return {
        "algorithm": spec.algorithm,
        "family": _family(spec.algorithm),
        "weight_set": spec.weight_set,
        "condition": spec.condition,
        "seed": spec.seed,
        "model": spec.model,
        "basis": spec.basis,
        "features": spec.features,
        "true_weights": tuple(float(x) for x in spec.true_over_features()),
    }


def regenerate(problem: IOCProblem, weights: np.ndarray) -> OracleSolution:
    """The optimal step for ``weights`` in the observation's basin (for scoring).

    Optima are local, and a plain solve from the observation may wander into another
    basin; so a proximal solve anchored at the observation comes first (from the projected
    observation) and an unanchored warm-started solve from it then converges to the nearby
    optimum. Run on the case's own problem after the algorithm, its solves are not counted
    as the algorithm's (the case keeps the algorithm's counts from before scoring).
    """
    near = problem.optimize(weights, proximal=SCORING_PROXIMAL)  # from the projected observation
    final = problem.optimize(weights, start=near) if near.success else near
    return final if final.success else problem.optimize(weights)


def _score(base: dict, outcome: Fit, problem: IOCProblem | MultiTrialProblem) -> CaseResult:
    result, spent = outcome.result, outcome.stats  # the algorithm's counts, before scoring adds its own
    assert result is not None
    est = unit(np.asarray(result.weights, dtype=float))
    regenerated = [regenerate(trial, est) for trial in problem.trials]
    errors = [
        trajectory_error(r.trajectory, trial.observed) if r.success else float("nan")
        for r, trial in zip(regenerated, problem.trials)
    ]
    traj_err = float(np.sum(errors))  # summed over trials, as the history's trajectory errors are
    return CaseResult(
        **base,
        status=result.status,
        reason="",
        weights=tuple(float(x) for x in est),
        weight_error=weight_error(est, np.array(base["true_weights"])),
        trajectory_error=traj_err,
        found_trajectory_error=_found(result),
        n_solves=spent.forward_solves,
        wall_time=outcome.wall_time,
        history=tuple(h.to_dict() for h in result.history),
        chosen_iteration=result.chosen_iteration,
        oracle=spent.to_dict(),
        notes=dict(result.notes),
        scoring_status=", ".join(r.status for r in regenerated),
        uncertainty=None if result.uncertainty is None else result.uncertainty.to_dict(),
        covered=None if result.uncertainty is None else result.uncertainty.contains(np.array(base["true_weights"])),
        model_fit=None if result.model_fit is None else result.model_fit.to_dict(),
        provenance=provenance(),
    )


def _found(result: IOCResult) -> float | None:
    """The paper's trajectory error of the step the IOC found for its output (if it has one)."""
    i = result.chosen_iteration
    if i is None:
        return None
    error = float(result.history[i].trajectory_error)
    return error if np.isfinite(error) else None


def _failed(base: dict, reason: str, outcome: Fit | None = None) -> CaseResult:
    n = len(base["features"])
    return CaseResult(
        **base,
        status="failed",
        reason=reason,
        weights=(float("nan"),) * n,
        weight_error=float("nan"),
        trajectory_error=float("nan"),
        n_solves=outcome.n_solves if outcome else 0,
        wall_time=outcome.wall_time if outcome else 0.0,
        oracle=outcome.stats.to_dict() if outcome else {},
        provenance=provenance(),
    )


__all__ = ["WEIGHT_SETS", "CaseResult", "CaseSpec", "run_case", "run_spec"]
