"""The one case protocol every track follows, so one runner and one board serve them all.

A case (:class:`Case`) is a key (its result file's name), an identity (the fields its
record must repeat), the inputs it needs prepared once per run (demonstrations, reference
steps: each an :class:`Input` that knows how to solve itself and where it is cached), a
run in a worker that returns a record, and the record of a case that could not run. A
record (:class:`Record`) serialises to JSON; a :class:`Track` parses it back, checked,
and says which case it holds, its suites (:class:`Suite`: the case lists a run is asked
for by name) and its part of the leaderboard (:class:`BoardSection`). The runner
(:mod:`ioc_bench.runner.run`), the executors, the result files
(:mod:`ioc_bench.runner.results`: atomic, validated, resumable), the time limits and the
leaderboard work on these alone; a track plugs in by registering its :class:`Track`
(:mod:`ioc_bench.runner.tracks`). This module imports nothing of the project, so a track
may import it without importing the runner.
"""

from __future__ import annotations

from collections.abc import Callable, Hashable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Protocol


class Input(Protocol):
    """Something a case needs that is solved once per run (and cached between runs)."""

    def __hash__(self) -> int: ...

    def prepare(self) -> Any:
        """The input's value: from the cache if its entry is this input's, else solved."""
        ...


class Record(Protocol):
    """What a case's run returns and its result file holds."""

    algorithm: str
    seed: int
    status: str
    reason: str
    wall_time: float

    @property
    def failed(self) -> bool: ...

    def headline(self) -> str:
        """The case's outcome in a few words (for progress lines)."""
        ...

    def to_dict(self) -> dict[str, Any]: ...


class Case(Protocol):
    """One case of a track."""

    track: str
    algorithm: str
    config: Mapping[str, Any]

    @property
    def key(self) -> str:
        """``<algorithm>/<name>``: the result file's path under a results folder, without suffix."""
        ...

    def path(self, root: str | Path) -> Path: ...

    @classmethod
    def identity_fields(cls) -> tuple[str, ...]:
        """The fields naming the case: a record must repeat them to be this case's."""
        ...

    def needs(self) -> Sequence[Input]: ...

    def run(self, inputs: Mapping[Hashable, Any]) -> Record: ...

    def failure(self, reason: str, config: Mapping[str, Any] | None = None) -> Record: ...

    def write_extras(self, root: str | Path, record: Record) -> None:
        """Write the files a record implies beside its result file (a figure), if missing."""
        ...


class Suite(Protocol):
    """A named list of cases of one algorithm (``ioc-bench run --suite NAME``)."""

    name: str
    description: str
    model: str

    def __len__(self) -> int: ...

    def cases(
        self, algorithm: str, config: Mapping[str, Any] | None = None, model: str | None = None, **options: Any
    ) -> Sequence[Case]: ...


def _owns_no_figure(path: str) -> bool:
    return False


@dataclass(frozen=True)
class BoardSection:
    """A track's part of the leaderboard; each callable is given the track's records only.

    Attributes:
        markdown: its Markdown lines, given its records and the figures beside the board it owns.
        files: its entries of ``leaderboard.json`` and its tables (name -> text); given no
            records, what a board without the track holds (a table's header, no entry or an empty one).
        tables: the names of the tables ``files`` gives, in the board's order of files.
        cases_key: the entry of ``leaderboard.json`` that keeps the track's cases.
        parse_kept: a case as ``cases_key`` keeps it, read back and checked (``ValueError``).
        summary: what the command line's ``--json`` reports of the records.
        owns_figure: whether a figure beside the board (a path relative to it) is the track's.
    """

    markdown: Callable[[Sequence[Any], Sequence[str]], list[str]]
    files: Callable[[Sequence[Any]], tuple[dict[str, Any], dict[str, str]]]
    tables: tuple[str, ...]
    cases_key: str
    parse_kept: Callable[[Any], Record]
    summary: Callable[[Sequence[Any]], dict[str, Any]]
    owns_figure: Callable[[str], bool] = _owns_no_figure


@dataclass(frozen=True)
class Track:
    """A track as the runner knows it: how its records are read back, its suites, its board section.

    Attributes:
        name: the ``track`` its records' JSON names (with ``names_itself`` false: its records
            name none, and a record that names no track is this track's; one track at most).
        parse: a checked record from decoded JSON (``ValueError`` naming the first problem).
        case_of: the case a record says it is (``ValueError`` if it is no valid case);
            given the record and the JSON's ``case_config`` (the config as written).
        suites: its suites by name (a live mapping: a suite added to it later is found too).
        board: its part of the leaderboard (None: its records are on no board).
        names_itself: whether its records' JSON carries ``track``.
    """

    name: str
    parse: Callable[[Any], Record]
    case_of: Callable[[Any, Mapping[str, Any] | None], Case]
    suites: Mapping[str, Suite] = field(default_factory=dict)
    board: BoardSection | None = None
    names_itself: bool = True
