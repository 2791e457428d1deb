"""A third track, made up here, plugs into the runner and the board through the registry alone.

The toy track guesses a number: its one suite has a case per seed, its records say how far
the guess fell, its board section is a line and a table. Nothing of the runner or of the
other tracks is changed for it; it is registered for the test and removed after.
"""

from __future__ import annotations

import json
from collections.abc import Hashable, Mapping, Sequence
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Any

import pytest

from ioc_bench.cli import main
from ioc_bench.runner.leaderboard import board_files, markdown, summary, write_leaderboard
from ioc_bench.runner.protocol import BoardSection, Track
from ioc_bench.runner.results import (
    board_records,
    load_results,
    results_directory,
    select_sources,
    stored_result,
    write_result,
)
from ioc_bench.runner.run import run_one
from ioc_bench.runner.tracks import TrackError, get_suite, register_track, suites, tracks, unregister_track
from ioc_bench.synthetic.case import CaseSpec

NAME = "toy"


@dataclass(frozen=True)
class ToyRecord:
    """A toy case's record: the guess and how far it fell from the seed."""

    algorithm: str
    seed: int
    guess: int
    status: str = "converged"
    reason: str = ""
    wall_time: float = 0.0
    track: str = NAME

    @property
    def failed(self) -> bool:
        return self.status == "failed"

    def headline(self) -> str:
        return f"guessed {self.guess}"

    def to_dict(self) -> dict[str, Any]:
        return asdict(self)


@dataclass(frozen=True)
class ToyCase:
    """A toy case: guess the seed."""

    algorithm: str
    seed: int
    config: Mapping[str, Any] = field(default_factory=dict)
    track: str = NAME

    @classmethod
    def identity_fields(cls) -> tuple[str, ...]:
        return ("algorithm", "seed")

    @property
    def key(self) -> str:
        return f"{self.algorithm}/toy__guess__seed{self.seed}"

    def path(self, root: str | Path) -> Path:
        return Path(root) / f"{self.key}.json"

    def needs(self) -> list:
        return []

    def run(self, inputs: Mapping[Hashable, Any]) -> ToyRecord:
        return ToyRecord(self.algorithm, self.seed, guess=self.seed + 1)

    def failure(self, reason: str, config: Mapping[str, Any] | None = None) -> ToyRecord:
        return ToyRecord(self.algorithm, self.seed, guess=0, status="failed", reason=reason)

    def write_extras(self, root: str | Path, record: ToyRecord) -> None:
        """Nothing beside the record."""


@dataclass(frozen=True)
class ToySuite:
    name: str = "toy-guesses"
    description: str = "guess each of three seeds"
    model: str = "none"
    seeds: tuple[int, ...] = (0, 1, 2)

    def __len__(self) -> int:
        return len(self.seeds)

    def cases(self, algorithm: str, config=None, model=None, **options) -> list[ToyCase]:
        return [ToyCase(algorithm, seed, dict(config or {})) for seed in self.seeds]


def parse(data: Any) -> ToyRecord:
    """A toy record from decoded JSON; ``ValueError`` for anything else."""
    if not isinstance(data, dict) or data.get("track") != NAME:
        raise ValueError("not a toy record")
    kept = {k: v for k, v in data.items() if k not in ("case_key", "case_config")}
    if set(kept) != {"algorithm", "seed", "guess", "status", "reason", "wall_time", "track"}:
        raise ValueError(f"a toy record has other fields: {sorted(kept)}")
    return ToyRecord(**kept)


def case_of(record: ToyRecord, case_config: Mapping[str, Any] | None) -> ToyCase:
    return ToyCase(record.algorithm, record.seed)


def section_lines(records: Sequence[ToyRecord], figures: Sequence[str]) -> list[str]:
    misses = sum(abs(r.guess - r.seed) for r in records)
    return ["## Toy track", "", f"{len(records)} guess(es), {misses} off in all."]


def files(records: Sequence[ToyRecord]) -> tuple[dict[str, Any], dict[str, str]]:
    rows = "".join(f"{r.algorithm},{r.seed},{r.guess}\n" for r in records)
    data = {"toy_cases": [r.to_dict() for r in records]} if records else {}
    return data, {"toy_cases.csv": "algorithm,seed,guess\n" + rows}


SECTION = BoardSection(
    markdown=section_lines,
    files=files,
    tables=("toy_cases.csv",),
    cases_key="toy_cases",
    parse_kept=parse,
    summary=lambda records: {"toy": len(records)} if records else {},
)
TOY = Track(NAME, parse, case_of, suites={"toy-guesses": ToySuite()}, board=SECTION)


@pytest.fixture
def toy_track():
    """The toy track, registered for one test."""
    register_track(TOY)
    yield TOY
    unregister_track(NAME)


def _run(root: Path) -> list[ToyCase]:
    """The toy suite's cases, run in this process and written as the runner writes results."""
    cases = get_suite("toy-guesses").cases("guesser")
    with results_directory(root):
        for case in cases:
            write_result(root, case, run_one(case, None))
    return cases


def test_the_toy_track_is_registered_after_the_built_in_ones_with_its_suite(toy_track):
    assert [t.name for t in tracks()][-1] == NAME
    assert {"synthetic", "human"} <= {t.name for t in tracks()}
    assert list(suites())[-1] == "toy-guesses" and len(get_suite("toy-guesses")) == 3
    with pytest.raises(TrackError, match="already registered"):
        register_track(Track(NAME, parse, case_of))
    with pytest.raises(TrackError, match="suite 'smoke' is already one of track 'synthetic'"):
        register_track(Track("other", parse, case_of, suites={"smoke": ToySuite("smoke")}))


def test_the_runner_writes_reads_and_resumes_toy_cases(toy_track, tmp_path):
    cases = _run(tmp_path)
    records = load_results(tmp_path)
    assert sorted((r.seed, r.guess) for r in records) == [(0, 1), (1, 2), (2, 3)]
    assert stored_result(tmp_path, cases[0]) == records[0]  # read back as its own case


def test_the_board_holds_the_toy_section_beside_the_synthetic_one(toy_track, tmp_path, make_result):
    _run(tmp_path / "results")
    write_result(tmp_path / "results", CaseSpec("log-barrier", "nominal", "ideal", 0), make_result())
    records = select_sources([tmp_path / "results"])
    text = markdown(records)
    assert text.index("## Synthetic track") < text.index("## Toy track") and "3 guess(es), 3 off in all." in text
    assert summary(records)["toy"] == 3 and "cells" in summary(records)

    paths = write_leaderboard(records, tmp_path / "board")
    assert [p.name for p in paths] == list(board_files()) and "toy_cases.csv" in board_files()
    assert (tmp_path / "board" / "toy_cases.csv").read_text().count("\n") == 4
    data = json.loads((tmp_path / "board" / "leaderboard.json").read_text())
    assert len(data["toy_cases"]) == 3 and len(data["cases"]) == 1 and "human_cases" not in data
    kept = board_records(tmp_path / "board" / "leaderboard.json")  # the board read back: every case of both tracks
    assert sorted(r.track if isinstance(r, ToyRecord) else "synthetic" for r in kept) == ["synthetic", *[NAME] * 3]


def test_the_command_line_lists_the_toy_suite_and_boards_its_cases(toy_track, tmp_path, capsys):
    _run(tmp_path / "results")
    assert main(["run", "--list", "--suite", "toy-guesses", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["suites"][0]["cases"] == 3
    assert main(["leaderboard", str(tmp_path / "results"), "--out", str(tmp_path / "board"), "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["toy"] == 3
    assert "## Toy track" in (tmp_path / "board" / "README.md").read_text()
