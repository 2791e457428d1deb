"""The one case protocol every track's cases follow, so one runner serves them all.

A case (:class:`Case`) is a key (its result file's name), an identity (the fields its
record must repeat), the inputs it needs prepared once per run (demonstrations, reference
steps: each an :class:`Input` that knows how to solve itself and where it is cached), a
run in a worker that returns a record, and the record of a case that could not run. A
record (:class:`Record`) serialises to JSON; a :class:`Track` parses it back, checked,
and says which case it holds. The runner (:mod:`ioc_bench.bench.runner`), the executors,
the result files (:mod:`ioc_bench.bench.results`: atomic, validated, resumable), the time
limits and the leaderboard work on these alone; the synthetic track
(:class:`~ioc_bench.bench.case.CaseSpec`) and the human track
(:class:`~ioc_bench.human.case.HumanCaseSpec`) are two implementations.
"""

from __future__ import annotations

from collections.abc import Callable, Hashable, Mapping, Sequence
from dataclasses import dataclass
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

    def needs(self) -> Sequence[Input]: ...

    def run(self, inputs: Mapping[Hashable, Any]) -> Record: ...

    def failure(self, reason: str, config: Mapping[str, Any] | None = None) -> Record: ...

    def write_extras(self, root: str | Path, record: Record) -> None:
        """Write the files a record implies beside its result file (a figure), if missing."""
        ...


@dataclass(frozen=True)
class Track:
    """How a track's records are read back.

    Attributes:
        name: the ``track`` a record's JSON names (the synthetic track's records name none).
        parse: a checked record from decoded JSON (``ValueError`` naming the first problem).
        case_of: the case a record says it is (``ValueError`` if it is no valid case);
            given the record and the JSON's ``case_config`` (the config as written).
    """

    name: str
    parse: Callable[[Any], Record]
    case_of: Callable[[Any, Mapping[str, Any] | None], Case]
