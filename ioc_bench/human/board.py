"""The human track's section of a leaderboard: the ranked opening and its headline
(:mod:`ioc_bench.human.opening`), the case figures, then the details
(:mod:`ioc_bench.human.summary`)."""

from __future__ import annotations

from collections.abc import Sequence

from ioc_bench.human.opening import figure_caption, figure_lines, ranking_lines, rankings
from ioc_bench.human.record import HumanResult
from ioc_bench.human.summary import detail_lines


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
    return "\n".join([*lines, *detail_lines(records)]) + "\n"
