"""What a run of human cases says, per algorithm and training design, and as Markdown.

Over a run's records (:class:`~ioc_bench.human.record.HumanResult`):

- the **run floor** per (subject, speed): the lowest RMSE any weights reached there in any
  case of the run (every algorithm's estimate, trained there or elsewhere, the nominal, the
  floor directions); skills are taken against it, so a weak case floor never flatters;
- per (algorithm, model, task, design): what the cost predicts of the change of gait with
  speed (the pooled R^2 of the change of the leg angles, of the prediction carried by
  continuation and of the cheapest of cold starts; how often the change beats copy and the
  population's change; the median step-length error; the family changes), then the angles
  (mean fit and prediction RMSE against the nominal's and the copy's, how many predictions
  beat each, the median skill), the ground force and the time spent;
- per (model, task, design): the model-free baselines over the same predictions (copy, the
  population's mean change, interpolation, the power law of step length);
- per (algorithm, subject): the spread of the weights inferred at each single training
  speed (the largest distance between two of them, and the range of each weight).

Records of different gait models (``HumanResult.model``) are never pooled: each model has
its own run floors, rows and weight spreads, and a row of a model other than the walker
names it beside the algorithm. Records of different cost bases (``HumanResult.basis``) have
their own rows and weight spreads (a row outside the effort basis names its basis too) and
share the run floors of their model and task: their reference steps are the same.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from itertools import combinations
from typing import Any

import numpy as np

from ioc_bench.bases import DEFAULT_BASIS
from ioc_bench.human.record import HumanResult
from ioc_bench.human.scoring import skill_score
from ioc_bench.model.catalogue import DEFAULT_MODEL


def run_floors(records: Sequence[HumanResult]) -> dict[tuple[str, str], float]:
    """Per (subject, speed code), the lowest RMSE any weights reached there in the run."""
    floors: dict[tuple[str, str], float] = {}
    for record in records:
        for code, score in record.scores.items():
            refs = [r.get("rmse_deg") for r in score.references.values()]
            for value in (score.rmse_deg, score.nominal_rmse_deg, *refs):
                if isinstance(value, (int, float)) and math.isfinite(value):
                    key = (record.subject, code)
                    floors[key] = min(floors.get(key, math.inf), value)
    return floors


def summarize(records: Sequence[HumanResult]) -> list[dict[str, Any]]:
    """One row per (algorithm, model, task, design), by algorithm, then model (the walker
    first), task, then one speed, two, ..., population; skills against the run floors of the
    row's model and task."""
    groups: dict[tuple[str, str, str, str, str], list[HumanResult]] = {}
    for record in records:
        groups.setdefault((record.algorithm, record.basis, record.model, record.task, record.design), []).append(record)
    floors = {
        (m, t): run_floors([r for r in records if (r.model, r.task) == (m, t)]) for _, _, m, t, _ in groups
    }  # fmt: skip

    def rank(key: tuple[str, str, str, str, str]) -> tuple:
        algorithm, basis, model, task, _ = key
        return (
            algorithm,
            basis != DEFAULT_BASIS,
            basis,
            model != DEFAULT_MODEL,
            model,
            task,
            _design_rank(groups[key][0]),
        )

    return [_row(*key, groups[key], floors[key[2], key[3]]) for key in sorted(groups, key=rank)]


#: The training designs in the order a board lists them (:func:`~ioc_bench.human.record.design_of`;
#: ``N speeds`` with several predicted come before the population).
DESIGNS = ("one speed", "two speeds", "leave one out", "population")


def _design_order(design: str) -> float:
    return DESIGNS.index(design) if design in DESIGNS else DESIGNS.index("population") - 0.5


def _design_rank(record: HumanResult) -> tuple[bool, int, int]:
    """Fewer training speeds first, then more predicted; the population design last."""
    return (bool(record.population), len(record.also_train), -len(record.predict))


def _row(
    algorithm: str, basis: str, model: str, task: str, design: str, cases: Sequence[HumanResult], floors
) -> dict[str, Any]:
    fits = [s.rmse_deg for r in cases for s in r.fits()]
    preds = [(r, s) for r in cases for s in r.predictions()]
    scores = [s for _, s in preds]
    copied = [s for s in scores if s.copy_from]
    carried = [s for s in scores if s.continued_from]
    skills = [
        skill_score(s.rmse_deg, s.nominal_rmse_deg, floors.get((r.subject, s.speed_code), math.nan))
        if math.isfinite(s.rmse_deg)
        else math.nan
        for r, s in preds
    ]
    return {
        "algorithm": algorithm,
        "basis": basis,
        "model": model,
        "task": task,
        "design": design,
        "cases": len(cases),
        "failed": sum(r.failed for r in cases),
        "predictions": len(preds),
        "failed_solves": sum(not math.isfinite(s.rmse_deg) for s in scores),
        "fit_rmse_deg": _mean(fits),
        "prediction_rmse_deg": _mean([s.rmse_deg for s in scores]),
        "nominal_rmse_deg": _mean([s.nominal_rmse_deg for s in scores]),
        "copy_rmse_deg": _mean([s.copy_rmse_deg for s in copied]),
        "beat_nominal": sum(s.beats_nominal is True for s in scores),
        "with_copy": len(copied),
        "beat_copy": sum(s.beats_copy is True for s in copied),
        "adaptation_deg": _mean([s.adaptation_deg for s in copied]),
        "copy_adaptation_deg": _mean([s.copy_adaptation_deg for s in copied]),
        "adaptation_beat_copy": sum(_below(s.adaptation_deg, s.copy_adaptation_deg) for s in copied),
        "change_r2": pooled_r2([(s.adaptation_deg, s.copy_adaptation_deg) for s in copied]),
        "cold_change_r2": pooled_r2([(s.cold_adaptation_deg, s.copy_adaptation_deg) for s in copied]),
        "change_beat_population": sum(_below(s.adaptation_deg, s.population_adaptation_deg) for s in copied),
        "with_population": sum(math.isfinite(s.population_adaptation_deg) for s in copied),
        "step_length_error": _median([s.step_length_error for s in scores]),
        "step_length_change_error": _median([s.step_length_change_error for s in copied]),
        "with_family": sum(s.family_changed is not None for s in carried),
        "family_changes": sum(s.family_changed is True for s in carried),
        "cold_other_family": sum(s.cold_same_family is False for s in carried),
        "ground_force_error": _mean([s.ground_force_error for s in scores]),
        "median_skill_run_floor": _median(skills),
        "time_s": sum(r.wall_time + r.scoring_time for r in cases),
    }


def baseline_rows(records: Sequence[HumanResult]) -> list[dict[str, Any]]:
    """The model-free baselines over each (model, task, design)'s predictions of a person's
    own steps (those of one algorithm: every algorithm predicts the same speeds): copy, the
    population's mean change, interpolation, and the power law of step length."""
    first: dict[tuple[str, str, str], tuple[str, str]] = {}
    for r in records:
        first.setdefault((r.model, r.task, r.design), (r.algorithm, r.basis))
    rows = []
    for (model, task, design), (algorithm, basis) in first.items():
        key = (algorithm, basis, model, task, design)
        scores = [s for r in records if (r.algorithm, r.basis, r.model, r.task, r.design) == key
                  for s in r.predictions() if s.copy_from]  # fmt: skip
        if not scores:
            continue
        inter = [s for s in scores if math.isfinite(s.interpolation_adaptation_deg)]
        rows.append({
            "model": model, "task": task, "design": design, "predictions": len(scores),
            "copy_rmse_deg": _mean([s.copy_rmse_deg for s in scores]),
            "population_rmse_deg": _mean([s.population_rmse_deg for s in scores]),
            "population_change_r2": pooled_r2([(s.population_adaptation_deg, s.copy_adaptation_deg) for s in scores]),
            "population_beat_copy": sum(_below(s.population_rmse_deg, s.copy_rmse_deg) for s in scores),
            "interpolated": len(inter),
            "interpolation_rmse_deg": _mean([s.interpolation_rmse_deg for s in inter]),
            "interpolation_change_r2": pooled_r2(
                [(s.interpolation_adaptation_deg, s.copy_adaptation_deg) for s in inter]
            ),
            "copy_step_length_error": _median([s.copy_step_length_error for s in scores]),
            "power_law_step_length_error": _median([s.power_law_step_length_error for s in scores]),
        })  # fmt: skip
    return sorted(rows, key=lambda r: (r["model"] != DEFAULT_MODEL, r["model"], r["task"], _design_order(r["design"])))


def pooled_r2(pairs: Sequence[tuple[float, float]]) -> float:
    """Pooled R^2 of the change over predictions given as (RMSE of the predicted change against
    the person's, RMSE of the person's change), all over the same knots:
    1 - sum error^2 / sum change^2 over the pairs whose two numbers are finite (NaN if none)."""
    kept = [(e, c) for e, c in pairs if math.isfinite(e) and math.isfinite(c)]
    total = sum(c * c for _, c in kept)
    return 1.0 - sum(e * e for e, _ in kept) / total if kept and total > 0 else math.nan


def weight_spread(records: Sequence[HumanResult]) -> list[dict[str, Any]]:
    """Per (algorithm, basis, model, task, subject): the weights inferred at each single training
    speed, the largest distance between two of them and each weight's range (needs two or more)."""
    groups: dict[tuple[str, str, str, str, str], dict[str, tuple[float, ...]]] = {}
    for r in records:
        if r.design == "one speed" and not r.failed:
            groups.setdefault((r.algorithm, r.basis, r.model, r.task, r.subject), {})[r.train] = r.weights
    rows = []
    for (algorithm, basis, model, task, subject), by_speed in groups.items():
        w = np.array(list(by_speed.values()))
        if len(w) < 2:
            continue
        distance = max(float(np.linalg.norm(a - b)) for a, b in combinations(w, 2))
        rows.append({
            "algorithm": algorithm, "basis": basis, "model": model, "task": task, "subject": subject,
            "speeds": sorted(by_speed),
            "largest_distance": distance,
            "ranges": [[float(lo), float(hi)] for lo, hi in zip(w.min(axis=0), w.max(axis=0))],
        })  # fmt: skip
    return rows


#: What the human section of a board says of its method, above its detailed tables.
METHOD = (
    "**Method.** A cost is inferred from a person's treadmill steps (WBDS: the leg segments' angles and rates "
    "of the mean step, mapped to the subject's own walker) at the training speed(s); the walker's optimum for it "
    "at the nearest training speed is carried to each other speed by continuation (warm, in steps of speed) and "
    "scored against the person's step there. *Task*: `speed` gives the walker the belt speed only (its step "
    "length and cadence are predictions); `speed-and-step` gives it the person's step length too. *Change R^2*: "
    "1 - sum |walker's change - person's change|^2 / sum |person's change|^2 of the leg angles between the "
    "training speed and the predicted one, pooled over a row's predictions (copying the person's training step "
    "scores 0). *Step length*: median |log| error of the walker's step length (at a given speed the cadence's is "
    "the same), and (*change*) of the person's step length at the training speed scaled by the walker's ratio. "
    "*Family changes*: predictions whose stance knee at heel strike moved more than 5 deg from the step they were "
    "carried from; *cold other family*: where the cheapest of cold starts lands on another family. Baselines: "
    "copy; the population's mean change between the two speeds (the other shipped subjects); interpolation in "
    "speed between two training speeds; the population's power law of step length L ~ v^b. RMSEs in degrees over "
    "the four leg segments; *nominal*: all weights equal. Designs: one training speed, two, all but one (*leave "
    "one out*), *population* (fitted on the other subjects). Times: the IOC's plus the forward solves'. See "
    "`docs/human.md`."
)


def detail_lines(records: Sequence[HumanResult]) -> list[str]:
    """The details of the human track's board section: the method, the change and step-length
    table, the baselines', the angles' table and the weight spread."""
    lines: list[str] = []
    lines += ["### Details", "", METHOD, "", "What each cost predicts of the change of gait with speed:", ""]
    rows = summarize(records)
    lines += _table(
        ["algorithm", "task", "design", "cases", "failed", "change R^2 (cold)", "change beat copy",
         "change beat population", "step length (change)", "family changes", "cold other family", "time (s)"],
        [[_algorithm(r), r["task"], r["design"], str(r["cases"]), _failures(r),
          f"{_cell(r['change_r2'])} ({_cell(r['cold_change_r2'])})", _count(r["adaptation_beat_copy"], r["with_copy"]),
          _count(r["change_beat_population"], r["with_population"]),
          f"{_cell(r['step_length_error'], 3)} ({_cell(r['step_length_change_error'], 3)})",
          _count(r["family_changes"], r["with_family"]), _count(r["cold_other_family"], r["with_family"]),
          _cell(r["time_s"], 0)] for r in rows],
    )  # fmt: skip
    base = baseline_rows(records)
    if base:
        lines += ["", "The model-free baselines over the same predictions:", ""]
        lines += _table(
            ["model", "task", "design", "predictions", "copy RMSE", "population RMSE (change R^2, beat copy)",
             "interpolation RMSE (change R^2)", "step length: copy", "step length: power law"],
            [[b["model"], b["task"], b["design"], str(b["predictions"]), _cell(b["copy_rmse_deg"]),
              f"{_cell(b['population_rmse_deg'])} ({_cell(b['population_change_r2'])}, "
              f"{_count(b['population_beat_copy'], b['predictions'])})",
              _interpolation(b),
              _cell(b["copy_step_length_error"], 3), _cell(b["power_law_step_length_error"], 3)] for b in base],
        )  # fmt: skip
    lines += ["", "The leg angles themselves:", ""]
    lines += _table(
        ["algorithm", "task", "design", "fit RMSE", "prediction RMSE", "nominal", "copy", "beat nominal", "beat copy",
         "ground force (BW)", "median skill"],
        [[_algorithm(r), r["task"], r["design"], _cell(r["fit_rmse_deg"]), _cell(r["prediction_rmse_deg"]),
          _cell(r["nominal_rmse_deg"]), _cell(r["copy_rmse_deg"]), _count(r["beat_nominal"], r["predictions"]),
          _count(r["beat_copy"], r["with_copy"]), _cell(r["ground_force_error"], 3),
          _cell(r["median_skill_run_floor"], 2)] for r in rows],
    )  # fmt: skip
    lines += _spread_lines(records)
    return lines


def _spread_lines(records: Sequence[HumanResult]) -> list[str]:
    spread = weight_spread(records)
    if not spread:
        return []
    bases = dict.fromkeys((r.basis, tuple(r.features)) for r in records)
    named = "; ".join(f"{b}: {', '.join(f)}" if len(bases) > 1 else ", ".join(f) for b, f in bases)
    lines = ["", f"Weights inferred at each single training speed ({named}):", ""]
    rows = [[_algorithm(row), row["task"], row["subject"], ", ".join(row["speeds"]), f"{row['largest_distance']:.3f}",
             ", ".join(f"{lo:.2f}-{hi:.2f}" for lo, hi in row["ranges"])] for row in spread]  # fmt: skip
    return lines + _table(["algorithm", "task", "subject", "speeds", "largest distance", "range of each weight"], rows)
    return lines


def _table(header: Sequence[str], rows: Sequence[Sequence[str]]) -> list[str]:
    return ["| " + " | ".join(header) + " |", "|" + "---|" * len(header), *("| " + " | ".join(r) + " |" for r in rows)]


def _interpolation(row: Mapping[str, Any]) -> str:
    if not row["interpolated"]:
        return "-"
    r2, n = _cell(row["interpolation_change_r2"]), row["interpolated"]
    return f"{_cell(row['interpolation_rmse_deg'])} ({r2}; {n} of {row['predictions']})"


def _count(n: int, of: int) -> str:
    return f"{n}/{of}" if of else "-"


def _algorithm(row: Mapping[str, Any]) -> str:
    """The algorithm's cell: its name, then the model's when it is not the walker and the
    basis's when it is not the effort basis."""
    qualifiers = [q for q, plain in ((row["model"], DEFAULT_MODEL), (row["basis"], DEFAULT_BASIS)) if q != plain]
    return f"{row['algorithm']} ({', '.join(qualifiers)})" if qualifiers else row["algorithm"]


def _failures(row: Mapping[str, Any]) -> str:
    solves = f" (+{row['failed_solves']} solves)" if row["failed_solves"] else ""
    return f"{row['failed']}{solves}"


def _below(a: float, b: float) -> bool:
    return math.isfinite(a) and math.isfinite(b) and a < b


def _finite(values: Sequence[float]) -> list[float]:
    return [v for v in values if v is not None and math.isfinite(v)]


def _mean(values: Sequence[float]) -> float:
    kept = _finite(values)
    return float(np.mean(kept)) if kept else math.nan


def _median(values: Sequence[float]) -> float:
    kept = _finite(values)
    return float(np.median(kept)) if kept else math.nan


def _cell(value: float, digits: int = 2) -> str:
    return "-" if value is None or not math.isfinite(value) else f"{value:.{digits}f}"
