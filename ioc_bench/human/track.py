"""The human track's score: does a cost inferred at one speed predict the person's other speeds?

Real walking has no true weights, so an estimate is scored by prediction (issue 26). A case
is (subject, training speed, predicted speeds, algorithm, config, seed):

1. **Fit.** The algorithm runs on the observation of the person's step at the training speed
   (:func:`~ioc_bench.human.observe.human_observation`: the leg segments' angles and rates
   only) with the subject's walker and the trial's task, through the same
   :class:`~ioc_bench.ioc.problem.IOCProblem` as the synthetic cases; what it returns is
   checked by the plugin contract. A raise or a broken answer is a recorded failure (status
   ``failed`` with the reason), never an exception. With further training speeds
   (``also_train``) the algorithm gets every training step at once, as a
   :class:`~ioc_bench.ioc.problem.MultiTrialProblem` (one cost for several trials).
2. **Forward solves.** At the training speed and at each predicted speed the subject's walker
   is solved for that trial's task (speed and step length) with the estimated weights:
   ``starts`` seeded multi-starts, the cheapest feasible optimum kept (the walker has several
   families of optima for one cost, ``docs/human.md``; one start can land on a costlier one).
   Nothing of the person's step at that speed is used to start it.
3. **RMSE** in degrees of the four leg segments' angles against the person's step, knot by
   knot (:func:`~ioc_bench.human.observe.segment_rmse_deg`): the *fit* at the training
   speed, the *prediction* at the others.
4. **References**, solved the same way at each speed: the *nominal* weights (all equal: what
   a user without IOC would assume) and the *floor*, the lowest RMSE reached at that speed by
   any weights tried there: the estimate, the nominal and the :data:`FLOOR_WEIGHTS`
   directions. It is a floor over those weights only, not over every cost the model allows.
5. **Skill** per speed, :func:`skill_score`: (nominal - method) / (nominal - floor).

The nominal and floor solves depend only on the subject, the speed, the starts and the seed,
so they are solved once per process and shared by every case that needs them.
"""

from __future__ import annotations

import hashlib
import json
import math
import time
import traceback
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ioc_bench._version import __version__
from ioc_bench.bench.scoring import unit
from ioc_bench.checks import check_count, check_seed
from ioc_bench.features import cost_features
from ioc_bench.human.observe import human_observation, leg_angles, segment_rmse_deg
from ioc_bench.human.step import HumanStep, human_step
from ioc_bench.human.wbds import WbdsData, subject_number, table_speed_code
from ioc_bench.ioc.contract import check_result
from ioc_bench.ioc.problem import IOCProblem, MultiTrialProblem
from ioc_bench.ioc.registry import canonical_config, check_config, check_name, get_algorithm, make_algorithm
from ioc_bench.model.walker import WALKER
from ioc_bench.optimize import optimize_gait
from ioc_bench.weights import parse_weights

#: The features an IOC weighs on a human step: the walker's cost features (hip, knee, dtau).
FEATURES: tuple[str, ...] = tuple(cost_features(WALKER))
#: Label of the nominal reference (all weights equal).
NOMINAL = "nominal"
#: Weight directions also solved at every speed for the floor: the simplex lattice point
#: that fit 9 of the 12 shipped trials best in ``docs/human.md`` (hip, knee, dtau = 1, 4, 0).
FLOOR_WEIGHTS: tuple[str, ...] = ("1,4,0",)
#: Multi-start size of every forward solve (start 0 is the rough periodic guess).
DEFAULT_STARTS = 3
#: Most starts a case may ask for.
MAX_STARTS = 50
#: RMSE difference (deg) below which two fits count as equal in :func:`skill_score`.
SKILL_TOL = 1e-6
#: The shipped subjects and treadmill speeds.
SHIPPED_SUBJECTS: tuple[str, ...] = ("WBDS01", "WBDS02", "WBDS03")
SPEED_CODES: tuple[str, ...] = ("T03", "T04", "T05", "T06")
#: The built-in algorithms (``ioc-bench algorithms``).
BUILTINS: tuple[str, ...] = ("log-barrier", "analytic-center", "inverse-kkt", "bilevel", "single-level")


def skill_score(method: float, nominal: float, floor: float) -> float:
    """(nominal - method) / (nominal - floor): 1 when the method reaches the floor, 0 when it
    does as well as the nominal weights, negative when it does worse.

    When the nominal weights are the floor (within :data:`SKILL_TOL`) there was nothing to
    gain: the skill is 0 if the method matches them, and undefined (NaN) if it does worse,
    since any negative number would be arbitrary; an undefined skill never counts as beating
    the nominal. NaN also when any RMSE is not finite (a failed solve).

    Raises:
        ValueError: ``floor`` above ``method`` or ``nominal`` (it is their minimum or lower).
    """
    values = np.array([method, nominal, floor], dtype=float)
    if not np.all(np.isfinite(values)):
        return float("nan")
    if floor > min(method, nominal) + SKILL_TOL:
        raise ValueError(f"the floor {floor} is above the method's {method} or the nominal {nominal} RMSE")
    span = nominal - floor
    if span > SKILL_TOL:
        return float((nominal - method) / span)
    return 0.0 if method <= nominal + SKILL_TOL else float("nan")


# -- cases ---------------------------------------------------------------------------------


@dataclass(frozen=True)
class HumanCaseSpec:
    """One case of the human track, checked when made (``ValueError``, one line).

    Attributes:
        subject: ``WBDSnn``.
        train: the training speed's code (``T0n``).
        predict: the predicted speeds' codes (not the training speed, no repeats).
        algorithm: a registered algorithm's name.
        seed: seed of the algorithm and of every forward multi-start.
        config: the algorithm's config overrides (stored canonical).
        starts: multi-start size of every forward solve.
        floor_weights: extra weight directions solved at every speed for the floor.
        also_train: further training speeds: the algorithm is given every training speed's
            step at once (a :class:`~ioc_bench.ioc.problem.MultiTrialProblem`: one cost for
            several trials); ``train`` stays the one ``fit_rmse_deg`` reports.
    """

    subject: str
    train: str
    predict: tuple[str, ...]
    algorithm: str
    seed: int = 0
    config: Mapping[str, Any] = field(default_factory=dict)
    starts: int = DEFAULT_STARTS
    floor_weights: tuple[str, ...] = FLOOR_WEIGHTS
    also_train: tuple[str, ...] = ()

    def __post_init__(self) -> None:
        subject_number(self.subject)
        table_speed_code(self.train)
        if isinstance(self.also_train, str) or not isinstance(self.also_train, Sequence):
            raise ValueError(f"also_train must be a sequence of speed codes, got {self.also_train!r}")
        object.__setattr__(self, "also_train", tuple(self.also_train))
        for code in self.also_train:
            table_speed_code(code)
        if len(set(self.training)) != len(self.training):
            raise ValueError(f"a training speed is repeated in {', '.join(self.training)}")
        if isinstance(self.predict, str) or not isinstance(self.predict, Sequence):
            raise ValueError(f"predict must be a sequence of speed codes, got {self.predict!r}")
        object.__setattr__(self, "predict", tuple(self.predict))
        for code in self.predict:
            table_speed_code(code)
        both = [code for code in self.training if code in self.predict]
        if both:
            raise ValueError(f"the training speed {both[0]} is also a predicted speed")
        if len(set(self.predict)) != len(self.predict):
            raise ValueError(f"a predicted speed is repeated in {', '.join(self.predict)}")
        check_name(self.algorithm)
        object.__setattr__(self, "seed", check_seed(self.seed))
        object.__setattr__(self, "starts", check_count(self.starts, "starts", maximum=MAX_STARTS))
        object.__setattr__(self, "floor_weights", tuple(self.floor_weights))
        for text in self.floor_weights:
            parse_weights(text, FEATURES)
        config = check_config(self.config)
        object.__setattr__(self, "config", canonical_config(self.algorithm, config) if config else {})

    @property
    def training(self) -> tuple[str, ...]:
        """Every training speed: ``train``, then ``also_train``."""
        return (self.train, *self.also_train)

    @property
    def speeds(self) -> tuple[str, ...]:
        """The training speeds, then the predicted ones."""
        return (*self.training, *self.predict)

    @property
    def key(self) -> str:
        """Relative path of the case's result file, without suffix."""
        name = f"{self.subject}_{'+'.join(self.training)}__predict-{'-'.join(self.predict) or 'none'}__seed{self.seed}"
        options = {"config": dict(self.config), "starts": self.starts, "floor": list(self.floor_weights)}
        if options != {"config": {}, "starts": DEFAULT_STARTS, "floor": list(FLOOR_WEIGHTS)}:
            name += "__cfg" + hashlib.sha256(json.dumps(options, sort_keys=True).encode()).hexdigest()[:8]
        return f"{self.algorithm}/{name}"

    def identity(self) -> dict[str, Any]:
        """The fields naming the case (what a result file must match to be this case's);
        ``also_train`` only when there are further training speeds."""
        extra = {"also_train": list(self.also_train)} if self.also_train else {}
        return extra | {
            "subject": self.subject,
            "train": self.train,
            "predict": list(self.predict),
            "algorithm": self.algorithm,
            "seed": self.seed,
            "config": dict(self.config),
            "starts": self.starts,
            "floor_weights": list(self.floor_weights),
        }


#: The quick check: one subject, one training speed, one predicted speed, two families.
HUMAN_SMOKE: tuple[HumanCaseSpec, ...] = tuple(
    HumanCaseSpec("WBDS01", "T05", ("T04",), algorithm) for algorithm in ("inverse-kkt", "bilevel")
)
#: The track: every shipped subject, each speed as training speed (predicting the other
#: three), every built-in algorithm.
HUMAN: tuple[HumanCaseSpec, ...] = tuple(
    HumanCaseSpec(subject, train, tuple(s for s in SPEED_CODES if s != train), algorithm)
    for subject in SHIPPED_SUBJECTS
    for train in SPEED_CODES
    for algorithm in BUILTINS
)
#: The case lists by name (``ioc-bench human --suite NAME``).
HUMAN_SUITES: dict[str, tuple[HumanCaseSpec, ...]] = {"human-smoke": HUMAN_SMOKE, "human": HUMAN}


# -- forward solves ------------------------------------------------------------------------


@dataclass(frozen=True, eq=False)
class SolvedStep:
    """The walker's optimal step for some weights at one human trial's task, and its fit."""

    label: str
    status: str
    success: bool
    objective: float
    rmse_deg: float
    angles: np.ndarray | None
    wall_time: float

    def summary(self) -> dict[str, Any]:
        return {"status": self.status, "objective": self.objective, "rmse_deg": self.rmse_deg}


def solve_step(weights: Any, step: HumanStep, starts: int, seed: int, label: str = "") -> SolvedStep:
    """The cheapest feasible optimum of ``starts`` seeded starts for ``weights`` (over
    :data:`FEATURES`) on the subject's walker at ``step``'s task; a failed solve is a result."""
    t0 = time.perf_counter()
    demo = optimize_gait(weights, step.params, step.task, starts=starts, seed=seed, workers=1, verify=False)
    ok = bool(demo.solver.success)
    return SolvedStep(
        label=label,
        status=demo.solver.status,
        success=ok,
        objective=float(demo.solver.objective),
        rmse_deg=segment_rmse_deg(demo.trajectory, step) if ok else float("nan"),
        angles=leg_angles(demo.trajectory) if ok else None,
        wall_time=time.perf_counter() - t0,
    )


_REFERENCES: dict[tuple, SolvedStep] = {}


def reference_step(step: HumanStep, weights: str, starts: int, seed: int) -> SolvedStep:
    """:func:`solve_step` for named reference weights, solved once per process and step."""
    params = json.dumps(step.params.to_dict(), sort_keys=True, default=str)
    key = (
        step.subject,
        step.speed_code,
        step.task.speed,
        step.task.step_length,
        params,
        step.angles.tobytes(),
        weights,
        starts,
        seed,
    )
    if key not in _REFERENCES:
        numbers = (1.0,) * len(FEATURES) if weights == NOMINAL else weights
        _REFERENCES[key] = solve_step(numbers, step, starts, seed, weights)
    return _REFERENCES[key]


@dataclass(frozen=True, eq=False)
class SpeedScore:
    """The estimate's step at one speed against the person's and the references'.

    Attributes:
        speed_code: the trial's speed code.
        speed, step_length: its task, walker units.
        estimate: the estimated weights' step.
        references: the nominal's and each floor direction's step, by label.
        floor_rmse_deg: the lowest RMSE of the estimate and the references.
        floor_label: which weights reached it (``estimate``, ``nominal`` or a direction).
        skill: :func:`skill_score` of the estimate.
    """

    speed_code: str
    speed: float
    step_length: float
    estimate: SolvedStep
    references: dict[str, SolvedStep]
    floor_rmse_deg: float
    floor_label: str
    skill: float

    @property
    def nominal_rmse_deg(self) -> float:
        return self.references[NOMINAL].rmse_deg

    def to_dict(self, role: str, angles: bool = True) -> dict[str, Any]:
        """The record of this speed; ``role`` names the RMSE (``fit`` or ``prediction``)."""
        out = {
            f"{role}_rmse_deg": self.estimate.rmse_deg,
            "nominal_rmse_deg": self.nominal_rmse_deg,
            "floor_rmse_deg": self.floor_rmse_deg,
            "floor_weights": self.floor_label,
            "skill": self.skill,
            "status": self.estimate.status,
            "objective": self.estimate.objective,
            "speed": self.speed,
            "step_length": self.step_length,
            "solve_time": self.estimate.wall_time,
            "references": {k: v.summary() for k, v in self.references.items()},
        }
        if angles:
            out["angles"] = {
                k: _rounded(v.angles) for k, v in (("estimate", self.estimate), (NOMINAL, self.references[NOMINAL]))
            }
        return out


def _rounded(angles: np.ndarray | None) -> list | None:
    return None if angles is None else np.round(angles, 5).tolist()


def score_speed(
    weights: np.ndarray,
    step: HumanStep,
    starts: int = DEFAULT_STARTS,
    seed: int = 0,
    floor_weights: Sequence[str] = FLOOR_WEIGHTS,
) -> SpeedScore:
    """Solve ``weights`` at ``step``'s task, the references beside them, and score the fit."""
    estimate = solve_step(np.asarray(weights, dtype=float), step, starts, seed, "estimate")
    refs = {label: reference_step(step, label, starts, seed) for label in (NOMINAL, *floor_weights)}
    tried = {"estimate": estimate.rmse_deg} | {label: r.rmse_deg for label, r in refs.items()}
    finite = {label: rmse for label, rmse in tried.items() if np.isfinite(rmse)}
    floor_label = min(finite, key=finite.__getitem__) if finite else ""
    floor = finite.get(floor_label, float("nan"))
    return SpeedScore(
        speed_code=step.speed_code,
        speed=float(step.task.speed),
        step_length=float(step.task.step_length),
        estimate=estimate,
        references=refs,
        floor_rmse_deg=floor,
        floor_label=floor_label,
        skill=skill_score(estimate.rmse_deg, refs[NOMINAL].rmse_deg, floor),
    )


def score_weights(
    weights: Any,
    steps: Mapping[str, HumanStep],
    starts: int = DEFAULT_STARTS,
    seed: int = 0,
    floor_weights: Sequence[str] = FLOOR_WEIGHTS,
) -> dict[str, SpeedScore]:
    """Score weights over :data:`FEATURES` at each step (by speed code) of one subject.

    Raises:
        ValueError: no steps, steps of different subjects or walkers (weights learnt on one
            person's walker say nothing of another's steps), a key that is not its step's
            speed code, or weights (or floor directions) that are not over :data:`FEATURES`.
    """
    steps = dict(steps)
    if not steps:
        raise ValueError("no steps to score")
    _check_one_subject(steps)
    w = parse_weights(weights, FEATURES)
    check_count(starts, "starts", maximum=MAX_STARTS)
    check_seed(seed)
    for text in floor_weights:  # before any solve, not when the first reference is solved
        parse_weights(text, FEATURES)
    return {code: score_speed(w, step, starts, seed, floor_weights) for code, step in steps.items()}


def _check_one_subject(steps: Mapping[str, HumanStep]) -> None:
    first = next(iter(steps.values()))
    for code, step in steps.items():
        if not isinstance(step, HumanStep):
            raise ValueError(f"steps must be HumanStep values, got {type(step).__name__} for {code!r}")
        if step.speed_code != code:
            raise ValueError(f"the step under {code!r} is {step.subject}'s step at {step.speed_code}")
        if step.subject != first.subject or step.params.to_dict() != first.params.to_dict():
            raise ValueError(f"steps of different subjects or walkers: {first.subject} and {step.subject}")


# -- running a case ------------------------------------------------------------------------


@dataclass(frozen=True)
class Estimate:
    """What the algorithm returned on the training step (weights NaN if it failed)."""

    status: str
    reason: str
    weights: tuple[float, ...]
    wall_time: float
    n_solves: int
    notes: dict[str, Any] = field(default_factory=dict)

    @property
    def failed(self) -> bool:
        return self.status == "failed"


def fit_human(spec: HumanCaseSpec, steps: Sequence[HumanStep]) -> Estimate:
    """Run ``spec``'s algorithm on the observation of the training ``steps`` (one problem,
    or a multi-trial problem for several, seeded by the case); an exception, an answer the
    plugin contract refuses, or several trials for an algorithm that takes one, is a failed
    estimate."""
    algo = make_algorithm(spec.algorithm, **spec.config)
    trials = [IOCProblem(human_observation(s), FEATURES, s.params, s.task, seed=spec.seed) for s in steps]
    problem = trials[0] if len(trials) == 1 else MultiTrialProblem(trials)
    nan = (float("nan"),) * len(FEATURES)
    if len(trials) > 1 and not algo.multi_trial:
        return Estimate(
            "failed", f"{spec.algorithm} does not handle several trials (its multi_trial is False)", nan, 0.0, 0
        )
    t0 = time.perf_counter()
    try:
        result = algo.fit(problem)
    except Exception as exc:  # the algorithm's fault is a recorded result, not a crash
        last = traceback.extract_tb(exc.__traceback__)[-1]
        reason = f"{type(exc).__name__}: {exc} (at {last.filename}:{last.lineno})"
        return Estimate("failed", reason, nan, time.perf_counter() - t0, problem.stats.forward_solves)
    wall = time.perf_counter() - t0
    reason = check_result(result, problem.n_features)
    if reason:
        return Estimate("failed", reason, nan, wall, problem.stats.forward_solves)
    weights = tuple(float(x) for x in unit(np.asarray(result.weights, dtype=float)))
    return Estimate(result.status, "", weights, wall, problem.stats.forward_solves, dict(result.notes))


@dataclass(frozen=True, eq=False)
class HumanResult:
    """The record of one human case: the estimate, its fit and its predictions."""

    spec: HumanCaseSpec
    family: str
    estimate: Estimate
    speeds: dict[str, SpeedScore]
    scoring_time: float
    version: str = __version__

    @property
    def failed(self) -> bool:
        return self.estimate.failed

    @property
    def fit_rmse_deg(self) -> float:
        score = self.speeds.get(self.spec.train)
        return score.estimate.rmse_deg if score else float("nan")

    def to_dict(self, angles: bool = True) -> dict[str, Any]:
        """The JSON record (``angles``: with each speed's walker angles, rad, for figures)."""
        fit = self.speeds.get(self.spec.train)
        return self.spec.identity() | {
            "family": self.family,
            "features": list(FEATURES),
            "status": self.estimate.status,
            "reason": self.estimate.reason,
            "weights": list(self.estimate.weights),
            "fit_rmse_deg": self.fit_rmse_deg,
            "fit": fit.to_dict("fit", angles) if fit else None,
            "also_fit": {c: self.speeds[c].to_dict("fit", angles) for c in self.spec.also_train if c in self.speeds},
            "predictions": {
                c: self.speeds[c].to_dict("prediction", angles) for c in self.spec.predict if c in self.speeds
            },
            "wall_time": self.estimate.wall_time,
            "n_solves": self.estimate.n_solves,
            "scoring_time": self.scoring_time,
            "notes": self.estimate.notes,
            "version": self.version,
        }


def load_steps(spec: HumanCaseSpec, data: WbdsData | None = None) -> dict[str, HumanStep]:
    """Every step ``spec`` needs, read and checked (``WbdsDataError`` names a bad file)."""
    data = data or WbdsData()
    return {code: human_step(data.trial(spec.subject, code)) for code in spec.speeds}


def run_human_case(spec: HumanCaseSpec, data: WbdsData | None = None) -> HumanResult:
    """Run and score one case (see the module docstring).

    Raises:
        ValueError: bad input before any solve (a file missing or malformed, an unknown
            algorithm or config); the algorithm's faults are recorded, not raised.
    """
    steps = load_steps(spec, data)
    make_algorithm(spec.algorithm, **spec.config)  # the name and the config, before any work
    estimate = fit_human(spec, [steps[code] for code in spec.training])
    t0 = time.perf_counter()
    speeds = {}
    if not estimate.failed:
        speeds = score_weights(estimate.weights, steps, spec.starts, spec.seed, spec.floor_weights)
    family = get_algorithm(spec.algorithm).family
    return HumanResult(spec, family, estimate, speeds, time.perf_counter() - t0)


# -- a run of many cases -------------------------------------------------------------------


def _method_rmse(score: Mapping[str, Any]) -> float | None:
    return score.get("fit_rmse_deg", score.get("prediction_rmse_deg"))


def _speed_scores(record: Mapping[str, Any]) -> list[tuple[str, str, Mapping[str, Any]]]:
    """(role, speed code, score) of a record's fit and predictions (none for a failed case)."""
    out = [("fit", record["train"], record["fit"])] if record.get("fit") else []
    out += [("fit", code, s) for code, s in (record.get("also_fit") or {}).items()]
    return out + [("prediction", code, s) for code, s in (record.get("predictions") or {}).items()]


def run_floors(records: Sequence[Mapping[str, Any]]) -> dict[tuple[str, str], float]:
    """The floor over a whole run: per (subject, speed), the lowest RMSE of any weights solved
    there by any case (every algorithm's estimate, trained there or elsewhere, the nominal and
    the floor directions)."""
    floors: dict[tuple[str, str], float] = {}
    for record in records:
        for _, code, score in _speed_scores(record):
            values = [_method_rmse(score), *(r.get("rmse_deg") for r in score.get("references", {}).values())]
            for value in values:
                if value is not None and math.isfinite(value):
                    key = (record["subject"], code)
                    floors[key] = min(floors.get(key, math.inf), value)
    return floors


def summarize(records: Sequence[Mapping[str, Any]]) -> dict[str, dict[str, Any]]:
    """Per algorithm over case records (:meth:`HumanResult.to_dict`): cases, failures, mean fit
    and prediction RMSE, predictions beating the nominal, the median skill against each case's
    own floor and against the run's floor (:func:`run_floors`), and the time spent."""
    floors = run_floors(records)
    by_algorithm: dict[str, list[Mapping[str, Any]]] = {}
    for record in records:
        by_algorithm.setdefault(record["algorithm"], []).append(record)
    return {name: _summary(cases, floors) for name, cases in by_algorithm.items()}


def _summary(cases: Sequence[Mapping[str, Any]], floors: Mapping[tuple[str, str], float]) -> dict[str, Any]:
    fits, preds, skills, run_skills = [], [], [], []
    for record in cases:
        for role, code, score in _speed_scores(record):
            method = _method_rmse(score)
            if role == "fit":
                fits.append(method)
                continue
            preds.append(method)
            skills.append(score.get("skill"))
            floor = floors.get((record["subject"], code))
            nominal = score.get("nominal_rmse_deg")
            ok = None not in (method, nominal, floor)
            run_skills.append(skill_score(method, nominal, floor) if ok else float("nan"))
    return {
        "cases": len(cases),
        "failed": sum(r["status"] == "failed" for r in cases),
        "fit_rmse_deg": _mean(fits),
        "prediction_rmse_deg": _mean(preds),
        "predictions": len(preds),
        "beat_nominal": sum(s is not None and math.isfinite(s) and s > 0 for s in run_skills),
        "median_skill": _median(skills),
        "median_skill_run_floor": _median(run_skills),
        "time_s": sum(r.get("wall_time", 0.0) + r.get("scoring_time", 0.0) for r in cases),
    }


def _finite(values: Sequence[float | None]) -> list[float]:
    return [v for v in values if v is not None and math.isfinite(v)]


def _mean(values: Sequence[float | None]) -> float:
    kept = _finite(values)
    return float(np.mean(kept)) if kept else float("nan")


def _median(values: Sequence[float | None]) -> float:
    kept = _finite(values)
    return float(np.median(kept)) if kept else float("nan")


def summary_markdown(summary: Mapping[str, Mapping[str, Any]]) -> str:
    """The per-algorithm summary (:func:`summarize`) as a Markdown table, for a leaderboard."""
    lines = [
        "| algorithm | cases | failed | fit RMSE (deg) | prediction RMSE (deg) | beat nominal | "
        "median skill (case floor) | median skill (run floor) | time (s) |",
        "|---|---|---|---|---|---|---|---|---|",
    ]
    for name, row in summary.items():
        cells = [
            name,
            str(row["cases"]),
            str(row["failed"]),
            _cell(row["fit_rmse_deg"], 2),
            _cell(row["prediction_rmse_deg"], 2),
            f"{row['beat_nominal']} of {row['predictions']}",
            _cell(row["median_skill"], 2),
            _cell(row["median_skill_run_floor"], 2),
            _cell(row["time_s"], 0),
        ]
        lines.append("| " + " | ".join(cells) + " |")
    return "\n".join(lines) + "\n"


def _cell(value: float | None, digits: int) -> str:
    return "-" if value is None or not math.isfinite(value) else f"{value:.{digits}f}"
