"""One human-track case: a cost inferred from a person's steps, scored on the steps it predicts.

A :class:`HumanCaseSpec` is the case's identity (subject, training and predicted speeds,
the training design, algorithm, config, seed, solve options), checked when made. It is a
case of the benchmark's one case protocol (:mod:`ioc_bench.runner.protocol`): it names its
result file (:attr:`~HumanCaseSpec.key`), the inputs the runner prepares once for every
case that shares them (:meth:`~HumanCaseSpec.needs`: the reference steps), and runs in a
worker (:meth:`~HumanCaseSpec.run`): the fit step every track shares
(:func:`ioc_bench.ioc.fit.fit`) on the observations of the training steps, then the
estimate's steps at every speed of the case, scored (:mod:`ioc_bench.human.scoring`).

Training designs: one speed (``train``), several at once (``also_train``: the algorithm
gets every training step as one multi-trial problem), leave one speed out (three training
speeds, one predicted), and a population design (``population``: the cost is fitted on
those other subjects' steps at the training speeds, and every speed of this subject is
predicted).

Tasks: what the walker is told at each speed (``task``). ``speed``: the belt speed only, the
step length and duration free, as on the synthetic track, so the step length and cadence
the cost predicts are scored; ``speed-and-step``: the person's measured step length too
(the walker's step length and cadence are then the person's by construction).

Predictions: the estimate's optimum at the nearest training speed (the cheapest of
``starts`` cold starts) carried to the predicted speed by continuation, so the change it
predicts is the cost's and not a switch between families of optima; the cheapest of cold
starts at the predicted speed is reported beside it (:mod:`ioc_bench.human.scoring`).

Models: a case maps the person's steps to one gait model (``model``: the paper's walker by
default, or another of :data:`HUMAN_MODELS`, on the subject's own body,
:mod:`ioc_bench.human.models`), and every step of it uses that model: the observation, the
IOC problem, the forward solves of the estimate and of the reference steps, their cache
keys and the figure.

Reference steps solved (INFO, with their time), read from the cache (DEBUG) or that cannot
be kept in it (WARNING) are logged to ``ioc_bench.human.case``.
"""

from __future__ import annotations

import hashlib
import json
import logging
import math
import time
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field, fields, replace
from functools import cached_property
from pathlib import Path
from typing import Any, ClassVar

import numpy as np

from ioc_bench.bases import DEFAULT_BASIS, get_basis
from ioc_bench.cache import CachedInput, cache_dir
from ioc_bench.fileio import atomic_write_json
from ioc_bench.human import baselines
from ioc_bench.human.models import HUMAN_MODELS as HUMAN_MODELS  # the case's models, named here too
from ioc_bench.human.models import check_human_model, subject_params
from ioc_bench.human.observe import human_observation
from ioc_bench.human.record import GIVEN_STEP, TASKS, TRACK, HumanResult, SpeedScore, design_of, read_record
from ioc_bench.human.scoring import (
    NOMINAL,
    SolvedStep,
    adaptation_deg,
    beats,
    continue_step,
    ground_force_error,
    nearest,
    rmse_deg,
    same_family,
    skill_score,
    solve_demo,
    solve_step,
)
from ioc_bench.human.step import HumanStep, human_step
from ioc_bench.human.wbds import WbdsData, subject_number, table_speed_code
from ioc_bench.ioc.fit import Fit, fit
from ioc_bench.ioc.problem import IOCProblem, MultiTrialProblem
from ioc_bench.ioc.registry import (
    canonical_config,
    check_algorithm_name,
    check_config,
    get_algorithm,
    make_algorithm,
)
from ioc_bench.model.catalogue import DEFAULT_MODEL, get_model
from ioc_bench.model.gait_model import GaitModel
from ioc_bench.paths import read_bytes
from ioc_bench.provenance import provenance
from ioc_bench.task import Task
from ioc_bench.validation import check_count, check_seed
from ioc_bench.weights import parse_weights

logger = logging.getLogger(__name__)

#: Weight directions also solved at every speed for the floor: the simplex lattice point
#: that fit 9 of the 12 shipped trials best (``docs/human.md``): (hip, knee, dtau) = (1, 4, 0).
FLOOR_WEIGHTS: tuple[str, ...] = ("1,4,0",)
#: Multi-start size of every forward solve (start 0 is the rough periodic guess).
DEFAULT_STARTS = 3
#: Most starts a case may ask for.
MAX_STARTS = 50
#: Revision of the reference steps' cache entries (bump when their solve changes).
REFERENCE_REVISION = 2
#: The subjects whose change between two speeds is the population baseline's (every subject
#: but the case's own): the shipped ones, for subjects read from any folder.
POPULATION_BASELINE: tuple[str, ...] = ("WBDS01", "WBDS02", "WBDS03")


@dataclass(frozen=True)
class HumanCaseSpec:
    """One case of the human track, checked when made (``ValueError``, one line).

    Attributes:
        subject: ``WBDSnn``, whose speeds are scored.
        train: the (first) training speed's code.
        predict: the predicted speeds' codes (not a training speed, unless ``population``).
        algorithm: a registered algorithm's name.
        seed: seed of the algorithm and of every forward multi-start.
        config: the algorithm's config overrides (stored canonical).
        starts: multi-start size of every forward solve.
        floor_weights: extra weight directions solved at every speed for the floor.
        also_train: further training speeds, all given to the algorithm at once.
        population: other subjects whose steps at the training speeds are fitted instead
            of this subject's (then every speed of this subject is predicted).
        model: the gait model the person's steps are mapped to.
        task: what the walker is told at each speed: ``speed`` (step length free) or
            ``speed-and-step`` (the person's step length too; the default, which every
            record without a task holds).
        basis: the cost basis the algorithm weighs and the estimate's steps are solved in
            (:data:`~ioc_bench.bases.COST_BASES`; the reference steps are the effort
            basis's whatever it is, so every basis is scored against the same ones).
        data: the WBDS folder (None: the shipped subset). Where the data lie, not what
            the case is: not part of its identity.
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
    population: tuple[str, ...] = ()
    model: str = DEFAULT_MODEL
    task: str = GIVEN_STEP
    basis: str = DEFAULT_BASIS
    data: str | None = field(default=None, compare=False)

    track = TRACK

    def __post_init__(self) -> None:
        subject_number(self.subject)
        table_speed_code(self.train)
        for name in ("predict", "also_train", "population", "floor_weights"):
            value = getattr(self, name)
            if isinstance(value, str) or not isinstance(value, Sequence):
                raise ValueError(f"{name} must be a sequence, got {value!r}")
            object.__setattr__(self, name, tuple(value))
        for code in (*self.also_train, *self.predict):
            table_speed_code(code)
        for other in self.population:
            subject_number(other)
        _distinct("training speed", self.training)
        _distinct("predicted speed", self.predict)
        _distinct("population subject", self.population)
        if self.subject in self.population:
            raise ValueError(f"{self.subject} is in its own population: a population design fits other subjects")
        both = [code for code in self.training if code in self.predict]
        if both and not self.population:
            raise ValueError(f"the training speed {both[0]} is also a predicted speed")
        check_human_model(self.model)
        if self.task not in TASKS:
            raise ValueError(f"unknown task {self.task!r}; a human case's task is one of {', '.join(TASKS)}")
        get_basis(self.basis)
        check_algorithm_name(self.algorithm)
        object.__setattr__(self, "seed", check_seed(self.seed))
        object.__setattr__(self, "starts", check_count(self.starts, "starts", maximum=MAX_STARTS))
        for text in self.floor_weights:
            parse_weights(text, self.features)
        config = check_config(self.config)
        object.__setattr__(self, "config", canonical_config(self.algorithm, config) if config else {})
        if self.data is not None and not isinstance(self.data, str):
            object.__setattr__(self, "data", str(self.data))

    # -- what the case is -----------------------------------------------------------------------
    @classmethod
    def identity_fields(cls) -> tuple[str, ...]:
        """The fields naming a case (a record's must match its file's name)."""
        return tuple(f.name for f in fields(cls) if f.init and f.compare)

    @cached_property
    def features(self) -> tuple[str, ...]:
        """The features the algorithm weighs: the case's basis on its model (computed once)."""
        return get_basis(self.basis).features(self.gait_model)

    @property
    def _solve_basis(self) -> tuple[str, ...] | None:
        """The basis the estimate's steps are solved in: the case's own (None: the model's
        default). Not the IOC's forward basis, which also carries the model's distractor
        features at weight 0: solving over it took 1.2-1.6x the scoring time on the
        energetics fits and moved one prediction to another optimum."""
        return None if self.basis == DEFAULT_BASIS else self.features

    @cached_property
    def gait_model(self) -> GaitModel:
        """The catalogue's model of :attr:`model` (resolved once per case)."""
        return get_model(self.model)

    @property
    def training(self) -> tuple[str, ...]:
        """Every training speed: ``train``, then ``also_train``."""
        return (self.train, *self.also_train)

    @property
    def scored(self) -> tuple[str, ...]:
        """This subject's speeds the case scores: its own training speeds (fits), then the
        predicted ones; with a population, the predicted ones only."""
        return self.predict if self.population else (*self.training, *self.predict)

    def role(self, code: str) -> str:
        return "fit" if code in self.training and not self.population else "prediction"

    @property
    def design(self) -> str:
        return design_of(len(self.training), len(self.predict), bool(self.population))

    @property
    def key(self) -> str:
        """Relative path of the case's result file, without suffix."""
        name = f"{self.subject}__train-{'+'.join(self.training)}"
        if self.population:
            name += f"__from-{'+'.join(self.population)}"
        name += f"__predict-{'-'.join(self.predict) or 'none'}__seed{self.seed}"
        if self.model != DEFAULT_MODEL:
            name += f"__model-{self.model}"
        if self.task != GIVEN_STEP:
            name += f"__task-{self.task}"
        if self.basis != DEFAULT_BASIS:
            name += f"__basis-{self.basis}"
        options = {"config": dict(self.config), "starts": self.starts, "floor": list(self.floor_weights)}
        if options != {"config": {}, "starts": DEFAULT_STARTS, "floor": list(FLOOR_WEIGHTS)}:
            name += "__cfg" + hashlib.sha256(json.dumps(options, sort_keys=True).encode()).hexdigest()[:8]
        return f"{self.algorithm}/{name}"

    def task_of(self, step: HumanStep) -> Task:
        """The walker's task at ``step``'s speed: its speed, and with ``speed-and-step`` its length."""
        return step.task if self.task == GIVEN_STEP else Task(step.task.speed)

    def path(self, root: str | Path) -> Path:
        return Path(root) / f"{self.key}.json"

    def identity(self) -> dict[str, Any]:
        return {name: _jsonable(getattr(self, name)) for name in self.identity_fields()}

    # -- the case protocol ----------------------------------------------------------------------
    def needs(self) -> list[ReferenceStep]:
        """The reference steps the case scores against (nominal and floor directions at every
        scored speed and training speed), prepared once by the runner for every case that
        shares them."""
        steps = self.steps()
        return [
            ReferenceStep(label, steps[code], self.starts, self.seed, self.model, self.task_of(steps[code]))
            for code in steps
            for label in self.labels
        ]

    @property
    def labels(self) -> tuple[str, ...]:
        return (NOMINAL, *self.floor_weights)

    def steps(self) -> dict[str, HumanStep]:
        """This subject's steps at every scored speed and at every training speed (read and
        checked once: ``WbdsDataError`` names a bad file)."""
        return self._steps

    @cached_property
    def _steps(self) -> dict[str, HumanStep]:
        codes = dict.fromkeys(self.training + self.scored)
        return {code: human_step(self._data.trial(self.subject, code)) for code in codes}

    def training_steps(self) -> list[HumanStep]:
        """The steps the algorithm is given: this subject's at the training speeds, or the
        population's."""
        if not self.population:
            steps = self.steps()
            return [steps[code] for code in self.training]
        return [human_step(self._data.trial(other, code)) for other in self.population for code in self.training]

    @cached_property
    def _data(self) -> WbdsData:
        return WbdsData(self.data)

    def _problem(self, step: HumanStep, model: GaitModel) -> IOCProblem:
        """The IOC problem of one training step on ``model`` (the subject's body on it)."""
        observed = human_observation(step, model=model)
        params = subject_params(step.params, model)
        return IOCProblem(observed, self.features, params, self.task_of(step), seed=self.seed, model=model)

    def run(self, inputs: Mapping[Any, Any]) -> HumanResult:
        """Run and score the case (in a worker): ``inputs`` maps :meth:`needs` to their steps."""
        model = self.gait_model
        trials = [self._problem(s, model) for s in self.training_steps()]
        algo = make_algorithm(self.algorithm, **self.config)  # once per case, handed to the fit
        outcome = fit(algo, trials[0] if len(trials) == 1 else MultiTrialProblem(trials))
        if outcome.failed:
            return self._record(outcome, {}, 0.0)
        t0 = time.perf_counter()
        weights = _unit(outcome.result.weights)
        steps = self.steps()
        cold, demos = {}, {}
        for code in dict.fromkeys((*self.scored, *self.sources().values())):
            task = self.task_of(steps[code])
            cold[code], demos[code] = solve_demo(
                weights, steps[code], self.starts, self.seed, "estimate", model, task, self._solve_basis
            )
        estimate = dict(cold)
        for code, source in self.sources().items():
            if code != source and cold[source].success:
                estimate[code] = continue_step(demos[source], self.task_of(steps[code]), "estimate", model)
            elif code != source:
                status = f"no start: the step at {source} failed ({cold[source].status})"
                estimate[code] = SolvedStep("estimate", status, False, math.nan, None, None, 0.0)
        refs = {code: {} for code in steps}
        for request in self.needs():
            refs[request.step.speed_code][request.label] = inputs[request]
        context = baseline_context(self.subject, [] if self.population else self.training_steps())
        scores = {}
        for code in self.scored:
            source = self.sources().get(code, "")
            score = score_speed(code, self.role(code), self._copy_source(code, steps), steps, estimate, refs)
            extra = prediction_scores(code, source, steps, estimate, cold, context, own=not self.population)
            scores[code] = replace(score, **extra)
        return self._record(outcome, scores, time.perf_counter() - t0)

    def sources(self) -> dict[str, str]:
        """Per predicted speed, the speed its step is carried from: the nearest training speed
        (for a population design, this subject's step there, itself predicted cold)."""
        steps = self.steps()
        if self.population:
            start = nearest([steps[c] for c in self.predict], steps[self.train]).speed_code
            return {code: start for code in self.predict}
        return {code: nearest([steps[c] for c in self.training], steps[code]).speed_code for code in self.predict}

    def failure(self, reason: str, config: Mapping[str, Any] | None = None) -> HumanResult:
        """The record of a case that could not run (it timed out, its worker died)."""
        return self._record(None, {}, 0.0, reason, dict(config or {}))

    def write_extras(self, root: str | Path, record: HumanResult) -> None:
        """The case's figure beside its result file (``.png``), if it is not there yet."""
        write_case_figures(root, [record], self.data)

    # -- scoring ----------------------------------------------------------------------------------
    def _copy_source(self, code: str, steps: Mapping[str, HumanStep]) -> str:
        """The training speed whose step the copy baseline copies for ``code`` ("" for a fit,
        or with a population: this subject's own steps were not trained on)."""
        if self.population or self.role(code) == "fit":
            return ""
        return nearest([steps[c] for c in self.training], steps[code]).speed_code

    def _record(
        self, outcome: Fit | None, scores: dict, scoring_time: float, reason: str = "", config: dict | None = None
    ) -> HumanResult:
        ok = outcome is not None and not outcome.failed
        n = len(self.features)
        return HumanResult(
            **{name: getattr(self, name) for name in self.identity_fields()} | {"config": dict(self.config)},
            family=_family(self.algorithm),
            features=self.features,
            status=outcome.result.status if ok else "failed",
            reason=outcome.reason if outcome is not None else reason,
            weights=tuple(_unit(outcome.result.weights)) if ok else (math.nan,) * n,
            wall_time=outcome.wall_time if outcome else 0.0,
            n_solves=outcome.n_solves if outcome else 0,
            scoring_time=scoring_time,
            scores=scores,
            notes=dict(outcome.result.notes) if ok else {},
            oracle=outcome.stats.to_dict() if outcome else {},
            provenance=provenance(),
        )


# -- records of cases ------------------------------------------------------------------------------
def parse_record(data: Any) -> HumanResult:
    """A :class:`HumanResult` from a result file's decoded JSON, checked for everything a file
    may have been edited into: its own values (:func:`~ioc_bench.human.record.read_record`) and
    that it is a valid case's record (:func:`check_record`); ``ValueError`` naming the first problem."""
    record = read_record(data)
    check_record(record)
    return record


def check_record(record: HumanResult) -> None:
    """``ValueError`` unless ``record`` is the record of a valid case: its identity makes a
    :class:`HumanCaseSpec` (subject, speeds, algorithm, config, options), its features are the
    case's model's, and its scores are the case's speeds with their roles (none if it failed)."""
    spec = HumanCaseSpec(**{f: getattr(record, f) for f in HumanCaseSpec.identity_fields()})
    if tuple(record.features) != spec.features:
        raise ValueError(f"features {list(record.features)} are not the model's {list(spec.features)}")
    expected = {} if record.failed else {code: spec.role(code) for code in spec.scored}
    if {c: s.role for c, s in record.scores.items()} != expected:
        raise ValueError(f"scores must be the case's speeds with their roles {expected}, got {sorted(record.scores)}")


def write_case_figures(out: str | Path, records: Sequence[HumanResult], data: str | None = None) -> list[Path]:
    """The figure (``.png`` beside its result file, :func:`ioc_bench.human.figures.plot_human_case`)
    of every case in ``records`` that has none yet in the results folder ``out`` (a run killed
    between a case's record and its figure leaves it to the next run)."""
    from ioc_bench.human.figures import plot_human_case  # matplotlib: only where figures are drawn

    written = []
    for record in records:
        spec = HumanCaseSpec(**{f: getattr(record, f) for f in HumanCaseSpec.identity_fields()}, data=data)
        path = spec.path(out).with_suffix(".png")
        if not path.is_file():
            steps = spec.steps()
            written.append(plot_human_case(record, {c: steps[c].angles for c in spec.scored}, path))
    return written


def score_speed(
    code: str,
    role: str,
    source: str,
    steps: Mapping[str, HumanStep],
    estimate: Mapping[str, SolvedStep],
    refs: Mapping[str, Mapping[str, SolvedStep]],
) -> SpeedScore:
    """The score at speed ``code`` (``role`` ``fit`` or ``prediction``): the estimate's step
    against the person's ``steps[code]`` and the reference steps ``refs[code]`` (by label,
    the nominal among them); with a ``source`` training speed, the copy baseline and the
    adaptation errors from it (``estimate`` and ``refs`` must then hold that speed too)."""
    person, mine, ref = steps[code], estimate[code], refs[code]
    nominal = ref[NOMINAL]
    rmses = {"estimate": mine.rmse_deg(person)} | {label: r.rmse_deg(person) for label, r in ref.items()}
    finite = {label: v for label, v in rmses.items() if math.isfinite(v)}
    floor_label = min(finite, key=finite.__getitem__) if finite else ""
    floor = finite.get(floor_label, math.nan)
    there = steps[source] if source else None
    copy = rmse_deg(there.angles, person.angles) if there else math.nan
    return SpeedScore(
        speed_code=code,
        role=role,
        speed=float(person.task.speed),
        step_length=float(person.task.step_length),
        status=mine.status,
        objective=mine.objective,
        rmse_deg=rmses["estimate"],
        nominal_rmse_deg=rmses[NOMINAL],
        floor_rmse_deg=floor,
        floor_weights=floor_label,
        skill=skill_score(rmses["estimate"], rmses[NOMINAL], floor),
        beats_nominal=beats(rmses["estimate"], rmses[NOMINAL]),
        copy_from=source,
        copy_rmse_deg=copy,
        beats_copy=beats(rmses["estimate"], copy),
        adaptation_deg=adaptation_deg(mine, estimate[source], person, there) if there else math.nan,
        copy_adaptation_deg=copy,
        nominal_adaptation_deg=adaptation_deg(nominal, refs[source][NOMINAL], person, there) if there else math.nan,
        ground_force_error=ground_force_error(mine, person),
        nominal_ground_force_error=ground_force_error(nominal, person),
        solve_time=mine.wall_time,
        references={label: {"status": r.status, "objective": r.objective, "rmse_deg": rmses[label]}
                    for label, r in ref.items()},
        angles={"estimate": _angles(mine), NOMINAL: _angles(nominal)},
    )  # fmt: skip


def baseline_context(subject: str, training: Sequence[HumanStep]) -> dict[str, Any]:
    """What the model-free baselines of ``subject``'s predictions need: the population's steps
    (every subject of :data:`POPULATION_BASELINE` but this one, shipped data, at every speed),
    the population's step-length exponent over them, and this subject's ``training`` steps
    (none for a population design)."""
    shipped = WbdsData()
    others = [s for s in POPULATION_BASELINE if s != subject]
    population = {(o, c): human_step(shipped.trial(o, c)) for o in others for c in shipped.speeds(o)}
    exponent = baselines.power_law_exponent(list(population.values())) if population else math.nan
    return {"population": population, "others": others, "exponent": exponent, "training": list(training)}


def prediction_scores(
    code: str,
    source: str,
    steps: Mapping[str, HumanStep],
    estimate: Mapping[str, SolvedStep],
    cold: Mapping[str, SolvedStep],
    context: Mapping[str, Any],
    own: bool,
) -> dict[str, Any]:
    """The scores of the step at ``code`` beyond its RMSEs: its step length, and for a step
    carried from ``source``, the change it predicts against the person's, the cheapest of cold
    starts there and the families; when the source is a step the cost was fitted on (``own``),
    the model-free baselines from it."""
    person, mine = steps[code], estimate[code]
    out: dict[str, Any] = {
        "step_length_walker": mine.step_length,
        "step_length_error": baselines.log_error(mine.step_length, person.task.step_length),
        "knee_at_strike_deg": mine.knee_at_strike_deg,
    }
    if not source or source == code:
        return out
    there, walker_there = steps[source], cold[source]
    change = person.angles - there.angles
    walker_change = None if mine.angles is None or walker_there.angles is None else mine.angles - walker_there.angles
    walker_ratio = mine.step_length / walker_there.step_length
    out |= {
        "continued_from": source,
        "continuation_solves": mine.solves,
        "change_r2": baselines.change_r2(walker_change, change),
        "step_length_change_error": baselines.log_error(there.task.step_length * walker_ratio, person.task.step_length),
        "family_changed": _negated(same_family(mine, walker_there)),
        "cold_rmse_deg": cold[code].rmse_deg(person),
        "cold_adaptation_deg": adaptation_deg(cold[code], walker_there, person, there),
        "cold_step_length": cold[code].step_length,
        "cold_same_family": same_family(mine, cold[code]),
    }
    if not own:
        return out
    out["copy_step_length_error"] = baselines.log_error(there.task.step_length, person.task.step_length)
    return out | _baseline_scores(person, there, context)


def _baseline_scores(person: HumanStep, there: HumanStep, context: Mapping[str, Any]) -> dict[str, Any]:
    """The model-free predictions of ``person`` from ``there``: the population's mean change,
    interpolation between training speeds, the population's power law of step length."""
    pop = context["population"]
    pairs = [(pop[o, there.speed_code], pop[o, person.speed_code]) for o in context["others"]
             if (o, there.speed_code) in pop and (o, person.speed_code) in pop]  # fmt: skip
    out: dict[str, Any] = {}
    mean_change = baselines.population_change(pairs)
    if mean_change is not None:
        out["population_rmse_deg"] = rmse_deg(there.angles + mean_change, person.angles)
        out["population_adaptation_deg"] = rmse_deg(mean_change, person.angles - there.angles)
    if math.isfinite(context["exponent"]):
        length = baselines.power_law_step_length(there, person.task.speed, context["exponent"])
        out["power_law_step_length_error"] = baselines.log_error(length, person.task.step_length)
    between = baselines.interpolate(context["training"], person.task.speed)
    if between is not None:
        out["interpolation_rmse_deg"] = rmse_deg(between.angles, person.angles)
        out["interpolation_adaptation_deg"] = rmse_deg(between.angles - there.angles, person.angles - there.angles)
        out["interpolation_step_length_error"] = baselines.log_error(between.step_length, person.task.step_length)
    return out


def _negated(value: bool | None) -> bool | None:
    return None if value is None else not value


@dataclass(frozen=True, eq=False)
class ReferenceStep(CachedInput):
    """A reference step to prepare: named weights (``nominal`` or a direction) solved at one
    human step's task on the case's model. Its result depends on the model and the subject's
    parameters on it, the task, the weights, the starts and the seed only, so it is solved
    once and kept in the cache (``<cache>/human-references/<key>.json``, checked against its
    key when read back). The key holds the model's name for every model but the walker
    (the default, keyed by its parameters alone), so no two models share an entry."""

    label: str
    step: HumanStep
    starts: int
    seed: int
    model: str = DEFAULT_MODEL
    task: Task | None = None

    @property
    def walker_task(self) -> Task:
        """The task solved: :attr:`task`, or the step's own."""
        return self.task or self.step.task

    revision: ClassVar[int] = REFERENCE_REVISION

    def payload(self) -> dict[str, Any]:
        """Every input of the reference step (the default model is not named in it)."""
        payload = {
            "label": self.label,
            "params": subject_params(self.step.params, get_model(self.model)).to_dict(),
            "task": self.walker_task.to_dict(),
            "knots": self.step.n_knots,
            "starts": self.starts,
            "seed": self.seed,
        }
        if self.model != DEFAULT_MODEL:
            payload["model"] = self.model
        return payload

    def prepare(self) -> SolvedStep:
        """The reference step, from the cache if its entry is this key's, else solved (and kept)."""
        path = cache_dir() / "human-references" / f"{self.key}.json"
        stored = _read_reference(path, self.key)
        if stored is not None:
            logger.debug("reference step %s read from the cache", self.key)
            return stored
        model = get_model(self.model)
        what = f"{self.label} on {self.step.subject} {self.step.speed_code} ({self.model})"
        logger.info("solving reference step %s: %s, %d start(s), seed %d", self.key, what, self.starts, self.seed)
        t0 = time.perf_counter()
        solved = solve_step(self.label, self.step, self.starts, self.seed, self.label, model, self.walker_task)
        logger.info("reference step %s solved in %.1f s", self.key, time.perf_counter() - t0)
        try:
            atomic_write_json(path, {"key": self.key, "step": solved.to_dict()})
        except (OSError, ValueError) as exc:  # a reference that cannot be kept is only solved again
            logger.warning("could not keep reference step %s in the cache: %s", self.key, exc)
        return solved


def _read_reference(path: Path, key: str) -> SolvedStep | None:
    from ioc_bench.validation import load_json

    if not path.is_file():
        return None
    try:
        data = load_json(read_bytes(path, 10_000_000, "reference step").decode())
        if data.get("key") != key:
            return None
        return SolvedStep.from_dict(data["step"])
    except (OSError, ValueError, KeyError, TypeError, AttributeError):
        return None


def _distinct(what: str, values: Sequence[str]) -> None:
    if len(set(values)) != len(values):
        raise ValueError(f"a {what} is repeated in {', '.join(values)}")


def _unit(weights: Any) -> np.ndarray:
    w = np.asarray(weights, dtype=float)
    return w / np.linalg.norm(w)


def _angles(step: SolvedStep) -> list | None:
    return None if step.angles is None else np.round(step.angles, 5).tolist()


def _family(algorithm: str) -> str:
    try:
        return get_algorithm(algorithm).family
    except ValueError:
        return ""


def _jsonable(value: Any) -> Any:
    if isinstance(value, tuple):
        return list(value)
    if isinstance(value, Mapping):
        return dict(value)
    return value
