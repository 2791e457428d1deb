"""The human track's section of a leaderboard: the ranked opening and its headline
(:mod:`ioc_bench.human.opening`), the case figures, then the details
(:mod:`ioc_bench.human.summary`); ``human_cases.csv`` and the ``human`` and ``human_cases``
of ``leaderboard.json``. :data:`SECTION` is what the board (:mod:`ioc_bench.runner.leaderboard`)
is handed."""

from __future__ import annotations

import csv
import io
import math
from collections.abc import Sequence
from typing import Any

from ioc_bench.human.case import parse_record
from ioc_bench.human.opening import figure_caption, figure_lines, ranking_lines, rankings
from ioc_bench.human.record import HumanResult
from ioc_bench.human.summary import detail_lines, summarize, weight_spread
from ioc_bench.runner.protocol import BoardSection


def markdown(records: Sequence[HumanResult], figures: Sequence[str] = ()) -> str:
    """The section as Markdown; ``figures`` are image paths relative to the page, of which the
    human case figures (named by their case keys) are shown."""
    lines = ["## Human track", ""]
    ranked = rankings(records)
    for ranking in ranked:
        lines += [*ranking_lines(ranking, several=len(ranked) > 1), ""]
    ours = [f for f in figures if figure_caption(f) is not None]
    if ours:
        lines += [*figure_lines(ours), ""]
    lines += [*detail_lines(records), "", "Every case's scored speeds are in [`human_cases.csv`](human_cases.csv)."]
    return "\n".join(lines) + "\n"


#: The columns of the human track's per-case table (one row per case and scored speed).
CSV_COLUMNS = (
    "subject", "algorithm", "basis", "model", "task", "design", "train", "population", "seed", "status",
    "features", "weights", "speed", "role", "continued_from", "rmse_deg", "copy_rmse_deg", "change_r2",
    "step_length_error", "knee_at_strike_deg", "reason",
)  # fmt: skip


def cases_csv(records: Sequence[HumanResult]) -> str:
    """Every human case's scored speeds as CSV rows (a failed case: one row without a speed)."""
    buffer = io.StringIO()
    writer = csv.writer(buffer, lineterminator="\n")
    writer.writerow(CSV_COLUMNS)
    for r in records:
        case = [
            r.subject, r.algorithm, r.basis, r.model, r.task, r.design, "+".join((r.train, *r.also_train)),
            "+".join(r.population), r.seed, r.status, " ".join(r.features),
            "" if r.failed else " ".join(_number(w) for w in r.weights),
        ]  # fmt: skip
        if not r.scores:
            writer.writerow([*case, "", "", "", "", "", "", "", "", " ".join(r.reason.split())])
        for code, s in r.scores.items():
            scored = [code, s.role, s.continued_from, _number(s.rmse_deg), _number(s.copy_rmse_deg)]
            scored += [_number(s.change_r2), _number(s.step_length_error), _number(s.knee_at_strike_deg), ""]
            writer.writerow([*case, *scored])
    return buffer.getvalue()


def _number(x: float | None) -> str:
    return "" if x is None or not math.isfinite(x) else f"{x:.6g}"


def files(records: Sequence[HumanResult]) -> tuple[dict[str, Any], dict[str, str]]:
    """The track's entries of ``leaderboard.json`` (its summary rows and weight spread, every
    case without its angle traces; none without records) and ``human_cases.csv``."""
    data = {}
    if records:
        data["human"] = {"rows": summarize(records), "weight_spread": weight_spread(records)}
        data["human_cases"] = [_without_angles(r.to_dict()) for r in records]
    return data, {"human_cases.csv": cases_csv(records)}


def _without_angles(record: dict) -> dict:
    for score in record.get("scores", {}).values():
        score.pop("angles", None)
    record.pop("oracle", None)
    return record


def summary(records: Sequence[HumanResult]) -> dict[str, Any]:
    """What ``--json`` reports of the track: its summary rows (nothing without records)."""
    return {"human": summarize(records)} if records else {}


def _lines(records: Sequence[HumanResult], figures: Sequence[str]) -> list[str]:
    return [markdown(records, figures).rstrip("\n")]


def _owns_figure(path: str) -> bool:
    return figure_caption(path) is not None


#: The human track's part of the board.
SECTION = BoardSection(
    markdown=_lines,
    files=files,
    tables=("human_cases.csv",),
    cases_key="human_cases",
    parse_kept=parse_record,
    summary=summary,
    owns_figure=_owns_figure,
)
