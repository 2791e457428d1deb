"""The record of one human-track case, as its result file holds it, checked when read back.

A record is the case (its identity, :class:`~ioc_bench.human.case.HumanCaseSpec`'s fields),
what the algorithm returned on the training steps, and one :class:`SpeedScore` per speed
of the case (the training speeds' fits and the predicted speeds). :func:`read_record`
checks everything a file may have been edited into that the record says of itself: every
field's type, every number's range, and every number that derives from others (the floor
is the lowest RMSE solved there, the skill the formula of the three RMSEs, the wins the
comparisons they name, the estimate of unit norm). Whether it is the record of a valid
case, whose speeds are the scores' speeds, is the case's to say:
:func:`ioc_bench.human.case.parse_record` reads a result file with both checks.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass, field
from typing import Any

import numpy as np

from ioc_bench._version import __version__
from ioc_bench.bases import DEFAULT_BASIS
from ioc_bench.human.scoring import SKILL_TOL, beats, skill_score
from ioc_bench.provenance import check_provenance
from ioc_bench.validation import json_fields, shown

#: The track's name, as result files record it.
TRACK = "human"
#: The tasks a human case gives the walker: the speed only, or the person's step length too.
SPEED_ONLY, GIVEN_STEP = "speed", "speed-and-step"
TASKS: tuple[str, ...] = (SPEED_ONLY, GIVEN_STEP)
#: How far a stored derived number may be from what it derives from (float round-trips).
DERIVED_TOLERANCE = 1e-9


@dataclass(frozen=True)
class SpeedScore:
    """The estimate's step at one speed of the case against the person's and the references'.

    Attributes:
        speed_code: the trial's speed code (``T0n``).
        role: ``fit`` (a training speed) or ``prediction``.
        speed, step_length: the person's speed and step length, walker units (with the
            ``speed-and-step`` task the walker is given both, so its step length and cadence
            are the person's by construction).
        status: IPOPT's status of the estimate's step.
        objective: its weighted cost.
        rmse_deg: leg-segment RMSE of the estimate's step against the person's (NaN if failed).
        nominal_rmse_deg: the nominal weights' RMSE.
        floor_rmse_deg: the lowest RMSE of the weights solved for this case here.
        floor_weights: which weights reached it (``estimate``, ``nominal`` or a direction).
        skill: :func:`~ioc_bench.human.scoring.skill_score` against that floor.
        beats_nominal: the estimate's RMSE is below the nominal's (None if either failed).
        copy_from: the training speed whose step the copy baseline copies ("" for a fit, or
            when the subject's own steps were not trained on).
        copy_rmse_deg: the copy baseline's RMSE (NaN without ``copy_from``).
        beats_copy: the estimate's RMSE is below the copy's (None without one).
        adaptation_deg: RMSE of the estimate's change of step from ``copy_from`` to here
            against the person's change.
        copy_adaptation_deg: the copy's (the person's change itself: it predicts none).
        nominal_adaptation_deg: the nominal weights' adaptation error.
        ground_force_error: RMSE (body weights) of the estimate's stance-foot force against
            the person's two feet together.
        nominal_ground_force_error: the nominal's.
        solve_time: seconds of the estimate's solves here.
        references: label -> ``{"status", "objective", "rmse_deg"}`` of each reference step.
        angles: ``estimate`` and ``nominal`` -> (T, 4) leg angles (rad), for the case figure.

    The estimate's step and what it predicts (NaN, or None, where it does not apply):

    Attributes:
        step_length_walker: the estimate's step length, leg lengths.
        step_length_error: ``|log|`` of its ratio to the person's (at a given speed, the
            cadence's error is the same number).
        knee_at_strike_deg: the estimate's stance knee flexion at heel strike (its family).
        continued_from: the speed whose optimum was carried here by continuation ("" for a
            fit, or for the speed a population design's predictions are carried from).
        continuation_solves: the warm solves it took.
        change_r2: 1 - |walker's change - person's change|^2 / |person's change|^2 of the leg
            angles from ``continued_from`` (copy: 0).
        step_length_change_error: ``|log|`` error of the person's step length at
            ``continued_from`` scaled by the walker's ratio of step lengths.
        family_changed: the prediction left the family of the step it was carried from.
        cold_rmse_deg, cold_adaptation_deg, cold_step_length: the cheapest optimum of cold
            starts here, scored as the estimate is.
        cold_same_family: it lands on the prediction's family.
        copy_step_length_error: the copy's step-length error (the person's at ``continued_from``).
        power_law_step_length_error: the population power law's (``L ~ v^b`` from the
            person's step length at ``continued_from``).
        population_rmse_deg, population_adaptation_deg: the person's step at
            ``continued_from`` plus the population's mean change between the two speeds.
        interpolation_rmse_deg, interpolation_adaptation_deg, interpolation_step_length_error:
            linear interpolation in speed between the training speeds either side.
    """

    speed_code: str
    role: str
    speed: float
    step_length: float
    status: str
    objective: float
    rmse_deg: float
    nominal_rmse_deg: float
    floor_rmse_deg: float
    floor_weights: str
    skill: float
    beats_nominal: bool | None
    copy_from: str
    copy_rmse_deg: float
    beats_copy: bool | None
    adaptation_deg: float
    copy_adaptation_deg: float
    nominal_adaptation_deg: float
    ground_force_error: float
    nominal_ground_force_error: float
    solve_time: float
    references: dict[str, dict[str, Any]] = field(default_factory=dict)
    angles: dict[str, list[list[float]] | None] = field(default_factory=dict)
    step_length_walker: float = math.nan
    step_length_error: float = math.nan
    knee_at_strike_deg: float = math.nan
    continued_from: str = ""
    continuation_solves: int = 0
    change_r2: float = math.nan
    step_length_change_error: float = math.nan
    family_changed: bool | None = None
    cold_rmse_deg: float = math.nan
    cold_adaptation_deg: float = math.nan
    cold_step_length: float = math.nan
    cold_same_family: bool | None = None
    copy_step_length_error: float = math.nan
    power_law_step_length_error: float = math.nan
    population_rmse_deg: float = math.nan
    population_adaptation_deg: float = math.nan
    interpolation_rmse_deg: float = math.nan
    interpolation_adaptation_deg: float = math.nan
    interpolation_step_length_error: float = math.nan


@dataclass(frozen=True)
class HumanResult:
    """One human-track case's record (what its result file holds).

    The identity fields are :class:`~ioc_bench.human.case.HumanCaseSpec`'s (a record without
    a ``basis`` was made in the effort basis); ``status`` is
    the algorithm's, or ``failed`` with ``reason`` (then no speed was scored); ``weights``
    are unit-norm over ``features`` (NaN if failed); ``wall_time`` and ``n_solves`` are the
    algorithm's, ``scoring_time`` the forward solves' after it; ``scores`` by speed code;
    ``provenance`` the commit and package versions the case ran with
    (:func:`ioc_bench.provenance.provenance`; ``{}`` in a record made before it was recorded).
    """

    subject: str
    train: str
    predict: tuple[str, ...]
    algorithm: str
    seed: int
    config: dict[str, Any]
    starts: int
    floor_weights: tuple[str, ...]
    also_train: tuple[str, ...]
    population: tuple[str, ...]
    model: str
    family: str
    features: tuple[str, ...]
    status: str
    reason: str
    weights: tuple[float, ...]
    wall_time: float
    n_solves: int
    scoring_time: float
    scores: dict[str, SpeedScore]
    notes: dict[str, Any] = field(default_factory=dict)
    oracle: dict[str, Any] = field(default_factory=dict)
    task: str = GIVEN_STEP
    basis: str = DEFAULT_BASIS
    track: str = TRACK
    version: str = __version__
    provenance: dict[str, Any] = field(default_factory=dict)

    @property
    def failed(self) -> bool:
        return self.status == "failed"

    @property
    def design(self) -> str:
        """The training design: ``one speed``, ``two speeds``, ``leave one out``, ``population``."""
        return design_of(len(self.also_train) + 1, len(self.predict), bool(self.population))

    def headline(self) -> str:
        """The case's outcome in a few words (for progress lines)."""
        if self.failed:
            return f"FAILED ({self.reason})"
        preds = self.predictions()
        mean = _mean([s.rmse_deg for s in preds])
        wins = sum(s.beats_nominal is True for s in preds)
        copies = [s for s in preds if s.copy_from]
        copy = f", copy {_mean([s.copy_rmse_deg for s in copies]):.1f} deg" if copies else ""
        errors = [s.adaptation_deg for s in preds if s.continued_from]
        change = f"; change error {_mean(errors):.1f} deg" if errors else ""
        lengths = _mean([s.step_length_error for s in preds])
        length = f", step length error {lengths:.3f}" if self.task == SPEED_ONLY else ""
        return f"predictions {mean:.1f} deg (beat nominal {wins}/{len(preds)}{copy}){change}{length}"

    def fits(self) -> list[SpeedScore]:
        return [s for s in self.scores.values() if s.role == "fit"]

    def predictions(self) -> list[SpeedScore]:
        return [s for s in self.scores.values() if s.role == "prediction"]

    def to_dict(self) -> dict[str, Any]:
        return asdict(self)


def _mean(values: list[float]) -> float:
    kept = [v for v in values if math.isfinite(v)]
    return float(np.mean(kept)) if kept else math.nan


def design_of(n_training: int, n_predicted: int, population: bool) -> str:
    """The name of a training design (see :attr:`HumanResult.design`)."""
    if population:
        return "population"
    if n_training == 1:
        return "one speed"
    if n_training == 2:
        return "two speeds"
    return "leave one out" if n_predicted == 1 else f"{n_training} speeds"


# -- reading back ----------------------------------------------------------------------------------

#: Keys the results folder adds to a record beside its fields; the folder checks them.
_FILE_KEYS = {"case_key": Any, "case_config": Any}


def read_record(data: Any) -> HumanResult:
    """A :class:`HumanResult` from decoded JSON, its own values checked (:func:`check_values`);
    ``ValueError`` naming the first problem. Not checked here: that it is a valid case's record
    (:func:`ioc_bench.human.case.parse_record` checks both)."""
    values = json_fields(HumanResult, data, extra=_FILE_KEYS, hints={"scores": dict[str, Any]})
    if values.get("track") != TRACK:
        raise ValueError(f"track must be {TRACK!r}, got {shown(values.get('track'))}")
    scores = values["scores"]
    values["scores"] = {code: SpeedScore(**json_fields(SpeedScore, s, f"scores[{code}]")) for code, s in scores.items()}
    record = HumanResult(**values)
    check_values(record)
    return record


def check_values(record: HumanResult) -> None:
    """``ValueError`` naming the first value of ``record`` out of range or inconsistent with
    the others (its identity is checked against a case by :func:`ioc_bench.human.case.check_record`)."""
    _check_weights(record)
    check_provenance(record.provenance)
    for name in ("wall_time", "scoring_time"):
        _non_negative(name, getattr(record, name), nan=False)
    if not 0 <= record.n_solves <= 10**9:
        raise ValueError(f"n_solves must be between 0 and 10**9, got {shown(record.n_solves)}")
    for code, score in record.scores.items():
        if score.speed_code != code:
            raise ValueError(f"scores[{code}] is the score of {shown(score.speed_code)}")
        _check_score(score)


def _check_weights(record: HumanResult) -> None:
    w = np.array(record.weights, dtype=float)
    if len(w) != len(record.features):
        raise ValueError(f"weights has {len(w)} entries for {len(record.features)} features")
    if record.failed:
        if not np.all(np.isnan(w)):
            raise ValueError("a failed case has no weights (NaN)")
        return
    if not np.all(np.isfinite(w)) or np.any(w < 0) or abs(np.linalg.norm(w) - 1) > 1e-6:
        raise ValueError(f"weights must be finite, non-negative and of unit norm, got {shown(list(record.weights))}")


def _non_negative(name: str, value: float, nan: bool = True) -> None:
    if (nan and math.isnan(value)) or 0 <= value < math.inf:
        return
    raise ValueError(f"{name} must be a non-negative number{' or null' if nan else ''}, got {shown(value)}")


def _check_score(s: SpeedScore) -> None:
    where = f"scores[{s.speed_code}]"
    for name in ("rmse_deg", "nominal_rmse_deg", "floor_rmse_deg", "copy_rmse_deg", "adaptation_deg",
                 "copy_adaptation_deg", "nominal_adaptation_deg", "ground_force_error",
                 "nominal_ground_force_error"):  # fmt: skip
        _non_negative(f"{where}.{name}", getattr(s, name))
    _non_negative(f"{where}.solve_time", s.solve_time, nan=False)
    if not (0 < s.speed < math.inf and 0 < s.step_length < math.inf):
        raise ValueError(f"{where}: speed and step_length must be positive, got {s.speed}, {s.step_length}")
    refs = [r.get("rmse_deg") for r in s.references.values()]
    tried = [x for x in [s.rmse_deg, s.nominal_rmse_deg, *refs] if isinstance(x, (int, float)) and math.isfinite(x)]
    if tried and not math.isclose(s.floor_rmse_deg, min(tried), rel_tol=0, abs_tol=DERIVED_TOLERANCE):
        raise ValueError(f"{where}.floor_rmse_deg {shown(s.floor_rmse_deg)} is not the lowest RMSE solved there")
    _same(f"{where}.skill", s.skill, _skill(s))
    _same(f"{where}.beats_nominal", s.beats_nominal, beats(s.rmse_deg, s.nominal_rmse_deg))
    copy = s.copy_rmse_deg if s.copy_from else math.nan
    if not s.copy_from and not all(math.isnan(getattr(s, k)) for k in ("copy_rmse_deg", "adaptation_deg")):
        raise ValueError(f"{where}: a copy baseline and an adaptation error need copy_from")
    _same(f"{where}.beats_copy", s.beats_copy, beats(s.rmse_deg, copy))
    _same(f"{where}.copy_adaptation_deg", s.copy_adaptation_deg, copy)  # both are the person's change
    for name in _PREDICTION_ERRORS:
        _non_negative(f"{where}.{name}", getattr(s, name))
    if s.continued_from and s.continued_from == s.copy_from:
        _same(f"{where}.change_r2", s.change_r2, _r2(s.adaptation_deg, s.copy_adaptation_deg))


#: The prediction's errors and baselines (non-negative, or NaN where they do not apply).
_PREDICTION_ERRORS = (
    "step_length_walker", "step_length_error", "step_length_change_error", "cold_rmse_deg", "cold_adaptation_deg",
    "cold_step_length", "copy_step_length_error", "power_law_step_length_error", "population_rmse_deg",
    "population_adaptation_deg", "interpolation_rmse_deg", "interpolation_adaptation_deg",
    "interpolation_step_length_error",
)  # fmt: skip


def _r2(error_deg: float, change_deg: float) -> float:
    """The R^2 of a change from its RMSE and the RMSE of the change itself (same knots)."""
    if not (math.isfinite(error_deg) and math.isfinite(change_deg)) or change_deg == 0:
        return math.nan
    return 1.0 - (error_deg / change_deg) ** 2


def _skill(s: SpeedScore) -> float:
    try:
        return skill_score(s.rmse_deg, s.nominal_rmse_deg, s.floor_rmse_deg)
    except ValueError:
        return math.nan


def _same(name: str, stored: Any, derived: Any) -> None:
    if isinstance(derived, float) and math.isnan(derived):
        ok = isinstance(stored, float) and math.isnan(stored)
    elif isinstance(derived, float):
        ok = isinstance(stored, float) and abs(stored - derived) <= max(SKILL_TOL, DERIVED_TOLERANCE * abs(derived))
    else:
        ok = stored is derived
    if not ok:
        raise ValueError(f"{name} is {shown(stored)}, but its RMSEs give {shown(derived)}")
