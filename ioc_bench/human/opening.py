"""The opening of the human board: one ranked table, the headline it supports, the figures.

:func:`rankings` puts every cost model (algorithm and basis) and every model-free baseline
(copy, the population's change, interpolation where it exists, the power law of step length)
in one table over the same predictions: those of the design every algorithm ran (one training
speed, on the shipped suites), per gait model and task. :func:`headline` says in two
sentences what the table's numbers say (computed from them, so they stay true when the
records change), and :func:`figure_caption` names a case figure from its file name.
:func:`ioc_bench.human.summary.markdown` assembles them above its detailed tables.
"""

from __future__ import annotations

import math
import re
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from ioc_bench.human.record import HumanResult, SpeedScore
from ioc_bench.human.summary import _algorithm, _cell, _design_order, _mean, _median, _table, pooled_r2
from ioc_bench.model.catalogue import DEFAULT_MODEL

#: The baselines' row labels.
COPY, POPULATION, INTERPOLATION, POWER_LAW = (
    "copy (baseline)",
    "population's change (baseline)",
    "interpolation (baseline)",
    "power law, step length only (baseline)",
)

#: Where a bootstrap over subjects has too few distinct resamples to give a 95 % interval.
_MIN_DISTINCT_RESAMPLES = 1000


@dataclass
class Ranking:
    """One ranked table: the rows of one (model, task) over one design's predictions.

    ``total`` is the number of predictions the design asks for (failed ones included);
    ``every`` says whether every cost model of the records ran the design."""

    model: str
    task: str
    design: str
    every: bool
    total: int
    subjects: list[str]
    rows: list[dict[str, Any]] = field(default_factory=list)


def ranking_design(records: Sequence[HumanResult]) -> tuple[str, bool]:
    """The design the ranking covers: the first (in board order) that every cost model of the
    records ran, and True; else the one most ran, and False."""
    groups: dict[tuple, set[str]] = {}
    for r in records:
        groups.setdefault((r.algorithm, r.basis, r.model, r.task), set()).add(r.design)
    designs = sorted({d for ds in groups.values() for d in ds}, key=lambda d: (_design_order(d), d))
    for design in designs:
        if all(design in ds for ds in groups.values()):
            return design, True
    return max(designs, key=lambda d: (sum(d in ds for ds in groups.values()), -designs.index(d))), False


def rankings(records: Sequence[HumanResult]) -> list[Ranking]:
    """One :class:`Ranking` per (model, task) over :func:`ranking_design`'s predictions (the
    walker first), its rows ordered by :func:`_rank_key`."""
    if not records:
        return []
    design, every = ranking_design(records)
    chosen = [r for r in records if r.design == design]
    pairs = sorted({(r.model, r.task) for r in chosen}, key=lambda p: (p[0] != DEFAULT_MODEL, p))
    out = []
    for model, task in pairs:
        mine = [r for r in chosen if (r.model, r.task) == (model, task)]
        keys = {key for r in mine for key in _keys(r)}
        reference = _reference_scores(mine)
        ranking = Ranking(model, task, design, every, len(keys), sorted({r.subject for r in mine}))
        groups: dict[tuple[str, str], list[HumanResult]] = {}
        for r in mine:
            groups.setdefault((r.algorithm, r.basis), []).append(r)
        rows = [_cost_row(cases, len(keys), reference) for cases in groups.values()]
        rows += _baseline_rows(list(reference.values()), len(keys))
        ranking.rows = sorted(rows, key=_rank_key)
        out.append(ranking)
    return out


def _keys(record: HumanResult) -> list[tuple]:
    """The predictions a case asks for (a failed case's too), as keys common to every algorithm."""
    codes = [c for c, s in record.scores.items() if s.role == "prediction"] if record.scores else record.predict
    return [(record.subject, record.train, record.also_train, record.population, code) for code in codes]


def _reference_scores(records: Sequence[HumanResult]) -> dict[tuple, SpeedScore]:
    """Per prediction key, one scored prediction (the baselines are the person's, the same in
    every algorithm's record of that prediction)."""
    out: dict[tuple, SpeedScore] = {}
    for r in sorted(records, key=lambda r: (r.algorithm, r.basis)):
        for key in _keys(r):
            score = r.scores.get(key[-1])
            if score is not None and key not in out:
                out[key] = score
    return out


def _cost_row(cases: Sequence[HumanResult], total: int, reference: dict[tuple, SpeedScore]) -> dict[str, Any]:
    first = cases[0]
    keys = [k for r in cases for k in _keys(r)]
    scores = [s for r in cases for s in r.predictions()]
    solved = [s for s in scores if math.isfinite(s.rmse_deg)]
    copied = [s for s in solved if s.copy_from]
    paired = [s for s in copied if math.isfinite(s.population_adaptation_deg)]
    return {
        "label": _algorithm({"algorithm": first.algorithm, "basis": first.basis, "model": first.model}),
        "kind": "cost",
        "change_r2": pooled_r2([(s.adaptation_deg, s.copy_adaptation_deg) for s in copied]),
        "step_length_error": _median([s.step_length_error for s in solved]),
        "rmse_deg": _mean([s.rmse_deg for s in solved]),
        "predictions": len(keys),
        "total": total,
        "failures": len(keys) - len(solved),
        # over the row's own solved predictions, for the headline's paired comparisons
        "copy_rmse_deg": _mean([s.copy_rmse_deg for s in copied]),
        "rmse_deg_with_copy": _mean([s.rmse_deg for s in copied]),
        "beat_copy": sum(s.beats_copy is True for s in copied),
        "with_copy": len(copied),
        "change_r2_with_population": pooled_r2([(s.adaptation_deg, s.copy_adaptation_deg) for s in paired]),
        "population_change_r2": pooled_r2([(s.population_adaptation_deg, s.copy_adaptation_deg) for s in paired]),
        "power_law_step_length_error": _median([s.power_law_step_length_error for s in solved]),
    }


def _baseline_rows(scores: Sequence[SpeedScore], total: int) -> list[dict[str, Any]]:
    """Copy, the population's change, interpolation and the power law over ``scores`` (one per
    prediction); a baseline without a finite number anywhere has no row."""

    def row(label: str, have: str, change: str | None, step: str | None, rmse: str | None) -> dict[str, Any] | None:
        kept = [s for s in scores if s.copy_from and math.isfinite(getattr(s, have))]
        if not kept:
            return None
        return {
            "label": label,
            "kind": "baseline",
            "change_r2": pooled_r2([(getattr(s, change), s.copy_adaptation_deg) for s in kept]) if change else math.nan,
            "step_length_error": _median([getattr(s, step) for s in kept]) if step else math.nan,
            "rmse_deg": _mean([getattr(s, rmse) for s in kept]) if rmse else math.nan,
            "predictions": len(kept),
            "total": total,
            "failures": None,
        }

    rows = [
        row(COPY, "copy_rmse_deg", "copy_adaptation_deg", "copy_step_length_error", "copy_rmse_deg"),
        row(POPULATION, "population_rmse_deg", "population_adaptation_deg", None, "population_rmse_deg"),
        row(INTERPOLATION, "interpolation_adaptation_deg", "interpolation_adaptation_deg",
            "interpolation_step_length_error", "interpolation_rmse_deg"),
        row(POWER_LAW, "power_law_step_length_error", None, "power_law_step_length_error", None),
    ]  # fmt: skip
    return [r for r in rows if r is not None]


def _rank_key(row: dict[str, Any]) -> tuple:
    """Rows over all the predictions first; then by change R^2 (higher first); rows without
    one by step-length error (lower first), then those with neither; ties by label."""
    partial = _partial(row)
    change, step = row["change_r2"], row["step_length_error"]
    if math.isfinite(change):
        return (partial, 0, -change, row["label"])
    return (partial, 1 if math.isfinite(step) else 2, step if math.isfinite(step) else 0.0, row["label"])


def ranking_lines(ranking: Ranking, several: bool = False) -> list[str]:
    """The ranked table with its caption, the headline and the intervals' sentence."""
    ran = "the design every algorithm ran" if ranking.every else "the design most algorithms ran"
    scope = f"{ranking.model}, task `{ranking.task}`" if several else f"task `{ranking.task}`"
    n = ranking.total
    caption = (
        f"**Ranked summary** over the *{ranking.design}* design ({ran}; {scope}): its {n} predictions of "
        f"{_plural(len(ranking.subjects), 'subject')} ({', '.join(ranking.subjects)}), pooled per row. Rank: change "
        "R^2, best first (of the leg angles' change from the training speed to the predicted one; copy scores 0, "
        "above 0 beats it); then rows without one (the power law predicts step length only) by step-length error; "
        f"rows over fewer predictions (k/{n}) last. Step length: median |log| error; leg angles: mean RMSE over the "
        "four leg segments; *failures*: predictions without a walker step, left out of the scores."
    )
    rows = [
        [str(i), row["label"], _cell(row["change_r2"]), _cell(row["step_length_error"], 3), _cell(row["rmse_deg"]),
         f"{row['predictions']}/{row['total']}", "-" if row["failures"] is None else str(row["failures"])]
        for i, row in enumerate(ranking.rows, 1)
    ]  # fmt: skip
    header = ["#", "model", "change R^2", "step length error", "leg-angle RMSE (deg)", "predictions", "failures"]
    return [caption, "", *_table(header, rows), "", headline(ranking), "", _interval_sentence(ranking)]


def headline(ranking: Ranking) -> str:
    """What the ranked table says, from its numbers: who ranks first on the change, how many
    cost models beat the population's change and copy's angles, and the power law's step length."""
    costs = [r for r in ranking.rows if r["kind"] == "cost"]
    ranked = [r for r in ranking.rows if math.isfinite(r["change_r2"])]
    if not costs or not ranked:
        return "No cost model has a change R^2 over these predictions."
    top = ranked[0]
    best = next((r for r in ranked if r["kind"] == "cost"), None)
    first = f"On the change of gait with speed, {_name(top)} ranks first (change R^2 {_cell(top['change_r2'])})"
    if best is not None and best is not top:
        first += f"; the best cost model, {_name(best)}, scores {_cell(best['change_r2'])}"
    compared = [r for r in costs if math.isfinite(r["change_r2_with_population"])
                and math.isfinite(r["population_change_r2"])]  # fmt: skip
    if compared:
        wins = sum(r["change_r2_with_population"] > r["population_change_r2"] for r in compared)
        first += f", and {_count(wins, len(compared))} the population's change over the same predictions"
    copy = next((r["rmse_deg"] for r in ranking.rows if r["label"] == COPY), math.nan)
    second = _angles_sentence(costs, copy) + _step_length_clause(costs)
    return f"{first}. {second}."


def _angles_sentence(costs: Sequence[dict[str, Any]], copy: float) -> str:
    compared = [r for r in costs if math.isfinite(r["rmse_deg_with_copy"]) and math.isfinite(r["copy_rmse_deg"])]
    if not compared:
        return "No cost model's leg angles can be set against copy's"
    wins = sum(r["rmse_deg_with_copy"] < r["copy_rmse_deg"] for r in compared)
    best = min(compared, key=lambda r: (_partial(r), r["rmse_deg_with_copy"]))
    per = f"{sum(r['beat_copy'] for r in compared)} of {sum(r['with_copy'] for r in compared)}"
    return (
        f"On the leg angles themselves, {_count(wins, len(compared))} copying the person's training step "
        f"(copy {_cell(copy)} deg; the best cost model, {_name(best)}, {_cell(best['rmse_deg_with_copy'])} deg; "
        f"per prediction {per} beat copy)"
    )


def _step_length_clause(costs: Sequence[dict[str, Any]]) -> str:
    compared = [r for r in costs if math.isfinite(r["step_length_error"])
                and math.isfinite(r["power_law_step_length_error"])]  # fmt: skip
    if not compared:
        return ""
    wins = sum(r["step_length_error"] < r["power_law_step_length_error"] for r in compared)
    best = min(compared, key=lambda r: (_partial(r), r["step_length_error"]))
    return (
        f", and on step length {_count(wins, len(compared))} the power law over the same predictions "
        f"(the power law {_cell(best['power_law_step_length_error'], 3)}; the best cost model, {_name(best)}, "
        f"{_cell(best['step_length_error'], 3)})"
    )


def _count(wins: int, of: int) -> str:
    """``none of the 5 cost models beats``, ``2 of the 5 cost models beat``, ``all 5 cost models beat``."""
    if of == 1:
        return "the cost model beats" if wins else "the cost model does not beat"
    if wins == 0:
        return f"none of the {of} cost models beats"
    return f"all {of} cost models beat" if wins == of else f"{wins} of the {of} cost models beat"


#: How the headline names each baseline.
_NAMES = {COPY: "copying the person's training step", POPULATION: "the population's change",
          INTERPOLATION: "interpolation in speed", POWER_LAW: "the power law of step length"}  # fmt: skip


def _name(row: dict[str, Any]) -> str:
    """A row's name in a sentence: the baseline's, or the cost model's label (with the share of
    the predictions it covers when it covers fewer)."""
    if row["kind"] == "baseline":
        return _NAMES.get(row["label"], row["label"])
    if not _partial(row):
        return row["label"]
    share = f"over {row['predictions']} of {row['total']} predictions"
    label = row["label"]
    return f"{label[:-1]}; {share})" if label.endswith(")") else f"{label} ({share})"


def _partial(row: dict[str, Any]) -> bool:
    return row["predictions"] < row["total"]


def _plural(n: int, word: str) -> str:
    return f"{n} {word}" + ("" if n == 1 else "s")


def _interval_sentence(ranking: Ranking) -> str:
    n = len(ranking.subjects)
    distinct = math.comb(2 * n - 1, n)
    if distinct < _MIN_DISTINCT_RESAMPLES:
        return (
            f"No intervals: the predictions come from {_plural(n, 'subject')}, so a bootstrap over subjects has "
            f"{_plural(distinct, 'distinct resample')}, too few for a 95 % interval, and one over the predictions "
            "would count one "
            "person's speeds, which share a body and a cost, as independent draws."
        )
    return "No intervals: a bootstrap over subjects is not computed for this table yet."


# -- the case figures --------------------------------------------------------------------------

_FIGURE = re.compile(
    r"^(?P<algorithm>.+)_(?P<subject>[A-Za-z]+\d+)__train-(?P<train>[^_]+)(?:__from-(?P<population>[^_]+))?"
    r"__predict-(?P<predict>[^_]+)(?P<rest>(?:__[^_]+)*)$"
)


def figure_caption(path: str) -> str | None:
    """A short caption of a case figure from its file name (``<algorithm>_<case key>.png``):
    algorithm, subject, training and predicted speeds (and model, task, basis when named);
    None for a name that is not a case figure's."""
    match = _FIGURE.match(Path(path).stem)
    if match is None:
        return None
    g = match.groupdict()
    train = _listed(g["train"].split("+"))
    caption = f"{g['algorithm']}, {g['subject']}: trained at {train}"
    if g["population"]:
        caption += f" (population {', '.join(g['population'].split('+'))})"
    caption += f", predicting {', '.join(g['predict'].split('-'))}"
    extra = [part.replace("-", " ", 1) for part in g["rest"].split("__") if part and not part.startswith("seed")]
    return caption + (f" ({', '.join(extra)})" if extra else "")


def _listed(items: Sequence[str]) -> str:
    return items[0] if len(items) == 1 else f"{', '.join(items[:-1])} and {items[-1]}"


def figure_lines(figures: Sequence[str]) -> list[str]:
    """The figures as one paragraph of Markdown images (a gallery), each captioned from its name."""
    if not figures:
        return []
    images = [f"![{figure_caption(path) or Path(path).stem}]({path})" for path in figures]
    return [
        "Case figures (each speed's leg angles, then each prediction's change of angles against the person's):",
        "",
        " ".join(images),
    ]


__all__ = ["Ranking", "figure_caption", "figure_lines", "headline", "rankings"]
