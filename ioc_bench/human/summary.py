"""What a run of human cases says, per algorithm and training design, and as Markdown.

Over a run's records (:class:`~ioc_bench.human.record.HumanResult`):

- the **run floor** per (subject, speed): the lowest RMSE any weights reached there in any
  case of the run (every algorithm's estimate, trained there or elsewhere, the nominal, the
  floor directions); skills are taken against it, so a weak case floor never flatters;
- per (algorithm, design): cases and failures; mean fit and prediction RMSE; the copy
  baseline's mean RMSE over the same predictions; how many predictions beat the nominal
  (a prediction worse than the nominal is a loss, whatever its skill) and how many beat
  copying the person; the mean adaptation error against the copy's; the median skill;
  the time spent;
- per (algorithm, subject): the spread of the weights inferred at each single training
  speed (the largest distance between two of them, and the range of each weight).

Records of different gait models (``HumanResult.model``) are never pooled: each model has
its own run floors, rows and weight spreads, and a row of a model other than the walker
names it beside the algorithm.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from itertools import combinations
from typing import Any

import numpy as np

from ioc_bench.human.record import HumanResult
from ioc_bench.human.scoring import skill_score


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
    """One row per (algorithm, model, design), by algorithm, then model (the walker first),
    then one speed, two, ..., population; skills against the run floors of the row's model."""
    floors = {m: run_floors([r for r in records if r.model == m]) for m in {r.model for r in records}}
    groups: dict[tuple[str, str, str], list[HumanResult]] = {}
    for record in records:
        groups.setdefault((record.algorithm, record.model, record.design), []).append(record)
    order = sorted(groups, key=lambda key: (key[0], key[1] != "walker", key[1], _design_rank(groups[key][0])))
    return [_row(*key, groups[key], floors[key[1]]) for key in order]


def _design_rank(record: HumanResult) -> tuple[bool, int, int]:
    """Fewer training speeds first, then more predicted; the population design last."""
    return (bool(record.population), len(record.also_train), -len(record.predict))


def _row(algorithm: str, model: str, design: str, cases: Sequence[HumanResult], floors) -> dict[str, Any]:
    fits = [s.rmse_deg for r in cases for s in r.fits()]
    preds = [(r, s) for r in cases for s in r.predictions()]
    copied = [(r, s) for r, s in preds if s.copy_from]
    skills = [
        skill_score(s.rmse_deg, s.nominal_rmse_deg, floors.get((r.subject, s.speed_code), math.nan))
        if math.isfinite(s.rmse_deg)
        else math.nan
        for r, s in preds
    ]
    return {
        "algorithm": algorithm,
        "model": model,
        "design": design,
        "cases": len(cases),
        "failed": sum(r.failed for r in cases),
        "predictions": len(preds),
        "failed_solves": sum(not math.isfinite(s.rmse_deg) for _, s in preds),
        "fit_rmse_deg": _mean(fits),
        "prediction_rmse_deg": _mean([s.rmse_deg for _, s in preds]),
        "nominal_rmse_deg": _mean([s.nominal_rmse_deg for _, s in preds]),
        "copy_rmse_deg": _mean([s.copy_rmse_deg for _, s in copied]),
        "beat_nominal": sum(s.beats_nominal is True for _, s in preds),
        "with_copy": len(copied),
        "beat_copy": sum(s.beats_copy is True for _, s in copied),
        "adaptation_deg": _mean([s.adaptation_deg for _, s in copied]),
        "copy_adaptation_deg": _mean([s.copy_adaptation_deg for _, s in copied]),
        "adaptation_beat_copy": sum(_below(s.adaptation_deg, s.copy_adaptation_deg) for _, s in copied),
        "ground_force_error": _mean([s.ground_force_error for _, s in preds]),
        "median_skill_run_floor": _median(skills),
        "time_s": sum(r.wall_time + r.scoring_time for r in cases),
    }


def weight_spread(records: Sequence[HumanResult]) -> list[dict[str, Any]]:
    """Per (algorithm, model, subject): the weights inferred at each single training speed,
    the largest distance between two of them and each weight's range (needs two or more)."""
    groups: dict[tuple[str, str, str], dict[str, tuple[float, ...]]] = {}
    for r in records:
        if r.design == "one speed" and not r.failed:
            groups.setdefault((r.algorithm, r.model, r.subject), {})[r.train] = r.weights
    rows = []
    for (algorithm, model, subject), by_speed in groups.items():
        w = np.array(list(by_speed.values()))
        if len(w) < 2:
            continue
        distance = max(float(np.linalg.norm(a - b)) for a, b in combinations(w, 2))
        rows.append({
            "algorithm": algorithm, "model": model, "subject": subject, "speeds": sorted(by_speed),
            "largest_distance": distance,
            "ranges": [[float(lo), float(hi)] for lo, hi in zip(w.min(axis=0), w.max(axis=0))],
        })  # fmt: skip
    return rows


def markdown(records: Sequence[HumanResult]) -> str:
    """The human track's section of a leaderboard: the summary table and the weight spread."""
    rows = summarize(records)
    features = next((r.features for r in records), ())
    lines = [
        "| algorithm | design | cases | failed | fit RMSE | prediction RMSE | nominal | copy | beat nominal | "
        "beat copy | adaptation (copy) | adaptation beat copy | ground force (BW) | median skill | time (s) |",
        "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for row in rows:
        n, c = row["predictions"], row["with_copy"]
        cells = [
            _algorithm(row), row["design"], str(row["cases"]), _failures(row),
            _cell(row["fit_rmse_deg"]), _cell(row["prediction_rmse_deg"]), _cell(row["nominal_rmse_deg"]),
            _cell(row["copy_rmse_deg"]), f"{row['beat_nominal']}/{n}", f"{row['beat_copy']}/{c}" if c else "-",
            f"{_cell(row['adaptation_deg'])} ({_cell(row['copy_adaptation_deg'])})" if c else "-",
            f"{row['adaptation_beat_copy']}/{c}" if c else "-", _cell(row["ground_force_error"], 3),
            _cell(row["median_skill_run_floor"], 2), _cell(row["time_s"], 0),
        ]  # fmt: skip
        lines.append("| " + " | ".join(cells) + " |")
    spread = weight_spread(records)
    if spread:
        lines += ["", f"Weights inferred at each single training speed ({', '.join(features)}):", ""]
        lines += ["| algorithm | subject | speeds | largest distance | range of each weight |", "|---|---|---|---|---|"]
        for row in spread:
            ranges = ", ".join(f"{lo:.2f}-{hi:.2f}" for lo, hi in row["ranges"])
            speeds = ", ".join(row["speeds"])
            line = f"| {_algorithm(row)} | {row['subject']} | {speeds} | {row['largest_distance']:.3f} | {ranges} |"
            lines.append(line)
    return "\n".join(lines) + "\n"


def _algorithm(row: Mapping[str, Any]) -> str:
    """The algorithm's cell: its name, and the model's when it is not the walker."""
    return row["algorithm"] if row["model"] == "walker" else f"{row['algorithm']} ({row['model']})"


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
