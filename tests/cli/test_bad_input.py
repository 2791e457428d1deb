"""Every bad input exits with code 2 and one line, before any work: issue 12's list and more.

Each row of :data:`CASES` is a command line a user could type, with the files it needs
made in a fresh folder; the command must exit with the expected code, print exactly one
line on stderr (no traceback) and say what is wrong. :data:`API_CASES` does the same for
the Python API: one documented error type and a clear message. ``docs/bad_input.md`` is
the table of every input tried with its exit code and message; the last test checks it
is current, and ``IOC_BENCH_WRITE_DOCS=1 python -m pytest tests/cli/test_bad_input.py``
rewrites it.
"""

from __future__ import annotations

import json
import os
import zipfile
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pytest

import ioc_bench
from ioc_bench import Demonstration, DemonstrationFileError, Task, optimize_gait, run_case
from ioc_bench.bench import runner
from ioc_bench.bench.results import CaseSpec, results_directory, write_result
from ioc_bench.cli import main

DOC = Path(__file__).resolve().parents[2] / "docs" / "bad_input.md"
ISSUE, ADDED = "issue 12", "added"


# -- inputs --------------------------------------------------------------------------------------


def _with_meta(arrays: dict, **changes) -> dict:
    meta = json.loads(str(arrays["meta"]))
    for key, value in changes.items():
        meta[key] = value(meta) if callable(value) else value
    return arrays | {"meta": np.array(json.dumps(meta))}


#: Ways to spoil a good demonstration's arrays.
DEMO_MUTATIONS: dict[str, Callable[[dict], dict]] = {
    "meta-list": lambda a: a | {"meta": np.array(json.dumps([1, 2]))},
    "weights-list": lambda a: _with_meta(a, weights=[1, 1, 1]),
    "q-0d": lambda a: a | {"traj_q": np.array(1.0)},
    "tau-0d": lambda a: a | {"traj_tau": np.array(1.0)},
    "nan-weights": lambda a: _with_meta(a, weights=lambda m: m["weights"] | {"hip": float("nan")}),
    "nan-features": lambda a: _with_meta(a, features=lambda m: m["features"] | {"knee": float("nan")}),
    "meta-not-json": lambda a: a | {"meta": np.array("not json")},
    "schema-99": lambda a: _with_meta(a, schema=99),
    "missing-q": lambda a: {k: v for k, v in a.items() if k != "traj_q"},
    "solver-list": lambda a: _with_meta(a, solver=["Solve_Succeeded"]),
    "pickled": lambda a: a | {"lam_x": np.array([{"x": 1}], dtype=object)},
}


def make_demo(tmp: Path, good: Path, kind: str) -> Path:
    """A demonstration file spoilt in the way ``kind`` says."""
    path = tmp / f"{kind}.npz"
    if kind in DEMO_MUTATIONS:
        with np.load(good) as data:
            arrays = {k: data[k] for k in data.files}
        np.savez(path, **DEMO_MUTATIONS[kind](arrays))
    elif kind == "corrupted":
        with zipfile.ZipFile(good) as z:
            info = z.getinfo("traj_q.npy")
        data = bytearray(good.read_bytes())
        start = info.header_offset + 30 + len(info.filename) + len(info.extra)
        data[start + 20 : start + 40] = bytes(20)
        path.write_bytes(bytes(data))
    elif kind == "renamed-npy":
        np.save(tmp / "array.npy", np.zeros(3))
        (tmp / "array.npy").rename(path)
    elif kind == "truncated":
        path.write_bytes(good.read_bytes()[: good.stat().st_size // 2])
    elif kind == "not-npy-member":
        with zipfile.ZipFile(path, "w") as z:
            z.writestr("meta.npy", b"this is not an array")
    else:
        raise KeyError(kind)
    return path


def make_results(tmp: Path, kind: str, result) -> Path:
    """A results folder: ``valid`` (one good result) or one with a bad file of ``kind``."""
    root = tmp / f"results-{kind}"
    if kind == "missing":
        return root
    root.mkdir()
    if kind == "empty":
        return root
    algorithm = "log-barrier"
    path = write_result(root, CaseSpec(algorithm, "nominal", "ideal", 0), result)
    data = result.to_dict()
    bad = {
        "valid": None,
        "null": "null",
        "list": "[1, 2]",
        "wall-time": json.dumps(data | {"wall_time": "fast"}),
        "weights-2": json.dumps(data | {"weights": [0.5, 0.5]}),
        "unknown-field": json.dumps(data | {"surprise": 1}),
        "not-json": "{not json",
    }[kind]
    if bad is not None:
        path.write_text(bad)
    return root


@dataclass(frozen=True)
class Case:
    """One command line; ``{tmp}``, ``{file}``, ``{demo}``, ``{demo:<kind>}``, ``{res:<kind>}`` are made."""

    id: str
    source: str
    argv: tuple[str, ...]
    expect: str
    code: int = 2
    hold: str = ""  # a results folder another run holds while this one starts


def C(id: str, source: str, line: str, expect: str, code: int = 2, hold: str = "") -> Case:
    return Case(id, source, tuple(line.split()), expect, code, hold)


CASES: list[Case] = [
    # tracebacks
    C("ioc-config-negative", ISSUE, 'ioc --config {"n_random":-1}', "n_random must be >= 0"),
    C("ioc-config-choice", ISSUE, 'ioc --config {"forward_start":"nope"}', "forward_start must be 'warm' or 'cold'"),
    C("ioc-seed-negative", ISSUE, "ioc --seed -1", "must be >= 0"),
    C("gait-seed-negative", ISSUE, "gait --seed -1", "must be >= 0"),
    C("ioc-out-under-file", ISSUE, "ioc --out {file}/r.json", "cannot create {file}/r.json: {file} is not a dir"),
    C("gait-out-under-file", ISSUE, "gait --out {file}/demo.npz", "is not a directory"),
    C("replay-out-under-file", ISSUE, "replay {demo} --out {file}/sub", "is not a directory"),
    C("run-out-under-file", ISSUE, "run --out {file}/results", "is not a directory"),
    C("leaderboard-out-under-file", ISSUE, "leaderboard {res:valid} --out {file}/board", "is not a directory"),
    C("figures-out-under-file", ISSUE, "figures {res:valid} --out {file}/figs", "is not a directory"),
    C("replay-meta-list", ISSUE, "replay {demo:meta-list}", "'meta' header must be a JSON object"),
    C("replay-weights-list", ISSUE, "replay {demo:weights-list}", "weights must be a JSON object"),
    C("replay-q-0d", ISSUE, "replay {demo:q-0d}", "array q has shape ()"),
    C("replay-tau-0d", ISSUE, "replay {demo:tau-0d}", "array tau has shape ()"),
    C("replay-corrupted-member", ISSUE, "replay {demo:corrupted}", "not a readable .npz"),
    C("replay-renamed-npy", ISSUE, "replay {demo:renamed-npy}", "not a zip archive"),
    C("leaderboard-null-result", ISSUE, "leaderboard {res:null}", "expected a JSON object, got null"),
    C("figures-null-result", ISSUE, "figures {res:null} --out {tmp}/figs", "expected a JSON object, got null"),
    C("run-resume-null-result", ISSUE, "run --out {res:null}", "expected a JSON object, got null"),
    C("leaderboard-wall-time-text", ISSUE, "leaderboard {res:wall-time}", 'wall_time must be a number, got "fast"'),
    # wrong success
    C("run-config-unknown-field", ISSUE, 'run --config {"nope":1}', "unknown field(s) nope"),
    C("figures-wall-time-text", ISSUE, "figures {res:wall-time} --out {tmp}/figs", "wall_time must be a number"),
    C("replay-nan-weights", ISSUE, "replay {demo:nan-weights}", "weights['hip'] must be a finite number"),
    C("replay-nan-features", ISSUE, "replay {demo:nan-features}", "features['knee'] must be a finite number"),
    # two lines
    C("ioc-config-unknown-field", ISSUE, 'ioc --config {"nope":1}', "unknown field(s) nope"),
    # added
    C("ioc-config-float-for-int", ADDED, 'ioc --config {"n_random":1.5}', "n_random must be an integer"),
    C("ioc-config-number-for-text", ADDED, 'ioc --config {"forward_start":3}', "must be a string"),
    C(
        "ioc-config-bad-list",
        ADDED,
        'ioc --algorithm analytic-center --config {"proximal":[1,"x"]}',
        "must be a list of finite numbers",
    ),
    C("ioc-config-nan", ADDED, 'ioc --config {"perturbation":NaN}', "must be a finite number"),
    C("ioc-config-not-object", ADDED, "ioc --config [1,2]", "must be a JSON object"),
    C("run-config-bool-for-int", ADDED, 'run --config {"n_random":true}', "n_random must be an integer"),
    C("ioc-algorithm-path", ADDED, "ioc --algorithm ../x", "unknown algorithm '../x'"),
    C("run-algorithm-path", ADDED, "run --algorithm ../x", "invalid algorithm name '../x'"),
    C("ioc-out-directory", ADDED, "ioc --out {tmp}", "is a directory"),
    C("ioc-out-png", ADDED, "ioc --out {tmp}/r.png", "names the JSON result"),
    C("gait-out-directory", ADDED, "gait --out {tmp}/dir.npz --weights 1,1,1", "is a directory"),
    C("gait-weights-inf", ADDED, "gait --weights 1e999,1,1", "finite"),
    C("gait-weights-four", ADDED, "gait --weights 1,2,3,4", "expected 3 weights"),
    C("gait-starts-zero", ADDED, "gait --starts 0", "must be >= 1"),
    C("table1-seed-negative", ADDED, "table1 --seed -1", "must be >= 0"),
    C("speed-repeats-zero", ADDED, "speed --repeats 0", "must be >= 1"),
    C("old-bench-command", ADDED, "bench", "invalid choice: 'bench'"),
    C("run-suite-unknown", ADDED, "run --suite nope", "unknown suite 'nope'"),
    C("run-time-limit-nan", ADDED, "run --time-limit nan", "must be a positive number"),
    C("run-workers-zero", ADDED, "run --workers 0", "must be >= 1"),
    C("run-address-without-ray", ADDED, "run --address 127.0.0.1:6379", "--address is for the ray executor"),
    C("run-ray-unreachable", ADDED, "run --executor ray --address 127.0.0.1:9", "cannot reach a Ray cluster"),
    C("run-ray-bad-address", ADDED, "run --executor ray --address nowhere:99999", "cannot reach a Ray cluster"),
    C("run-unreadable-result", ADDED, "run --out {res:not-json}", "not JSON"),
    C("run-results-in-use", ADDED, "run --out {res:valid}", "another run is writing", hold="{res:valid}"),
    C("replay-truncated", ADDED, "replay {demo:truncated}", "not a zip archive"),
    C("replay-not-npy-member", ADDED, "replay {demo:not-npy-member}", "not a readable .npz"),
    C("replay-pickled-member", ADDED, "replay {demo:pickled}", "not a readable .npz"),
    C("replay-meta-not-json", ADDED, "replay {demo:meta-not-json}", "'meta' header is not JSON"),
    C("replay-schema-99", ADDED, "replay {demo:schema-99}", "schema version 99"),
    C("replay-missing-array", ADDED, "replay {demo:missing-q}", "missing trajectory arrays ['q']"),
    C("replay-solver-list", ADDED, "replay {demo:solver-list}", "solver must be a JSON object"),
    C("replay-directory", ADDED, "replay {tmp}", "is a directory, not a demonstration file"),
    C("replay-missing", ADDED, "replay {tmp}/nope.npz", "demonstration file not found"),
    C("replay-steps-zero", ADDED, "replay {demo} --steps 0", "must be >= 1"),
    C("leaderboard-list-result", ADDED, "leaderboard {res:list}", "expected a JSON object, got list"),
    C("leaderboard-short-weights", ADDED, "leaderboard {res:weights-2}", "weights has 2 entries for 3 features"),
    C("leaderboard-unknown-field", ADDED, "leaderboard {res:unknown-field}", "unknown field(s) surprise"),
    C("leaderboard-empty-dir", ADDED, "leaderboard {res:empty}", "no case results"),
    C("leaderboard-missing-dir", ADDED, "leaderboard {res:missing}", "results directory not found"),
    C("figures-out-file", ADDED, "figures {res:valid} --out {file}", "exists and is not a directory"),
    C("figures-unknown-algorithm", ADDED, "figures {res:valid} --algorithm nope", "not in the results"),
    C("no-such-command", ADDED, "no-such-command", "invalid choice"),
]


@pytest.fixture(scope="module")
def good_demo(nominal_demo, tmp_path_factory) -> Path:
    return nominal_demo.save(tmp_path_factory.mktemp("good") / "good.npz")


class Workspace:
    """Makes the files a command line names, in one folder."""

    def __init__(self, tmp: Path, good_demo: Path, result):
        self.tmp, self.good_demo, self.result = tmp, good_demo, result
        (tmp / "file").write_text("a plain file")
        (tmp / "dir.npz").mkdir()

    def resolve(self, token: str) -> str:
        out = token.replace("{tmp}", str(self.tmp)).replace("{file}", str(self.tmp / "file"))
        while "{demo" in out or "{res:" in out:
            start = out.index("{")
            end = out.index("}", start)
            name = out[start + 1 : end]
            if name == "demo":
                value = self.good_demo
            elif name.startswith("demo:"):
                value = make_demo(self.tmp, self.good_demo, name[5:])
            else:
                value = make_results(self.tmp, name[4:], self.result) if not self._made(name) else self._made(name)
            out = out[:start] + str(value) + out[end + 1 :]
        return out

    def _made(self, name: str) -> Path | None:
        path = self.tmp / f"results-{name[4:]}"
        return path if path.exists() else None


ROWS: dict[str, tuple[str, str, int, str]] = {}
API_ROWS: dict[str, tuple[str, str, str]] = {}


@pytest.fixture
def no_work(monkeypatch):
    """Fail the test if any command gets as far as solving something."""

    def forbidden(*args, **kwargs):
        raise AssertionError("expensive work started before the input was checked")

    from ioc_bench.trajopt.forward_problem import ForwardProblem

    monkeypatch.setattr(runner, "prepare_demonstrations", forbidden)
    monkeypatch.setattr(ForwardProblem, "solve", forbidden)  # every solve, whoever asks
    monkeypatch.setattr(ForwardProblem, "__init__", forbidden)  # and every build


@pytest.mark.parametrize("case", CASES, ids=[c.id for c in CASES])
def test_bad_input_exits_2_with_one_line(case: Case, tmp_path, good_demo, make_result, capsys, no_work):
    space = Workspace(tmp_path, good_demo, make_result())
    argv = [space.resolve(a) for a in case.argv]
    hold = space.resolve(case.hold) if case.hold else None
    with pytest.raises(SystemExit) as exc:
        if hold:
            with results_directory(hold):
                main(argv)
        else:
            main(argv)
    err = capsys.readouterr().err
    lines = err.splitlines()
    assert exc.value.code == case.code, err
    assert len(lines) == 1 and "Traceback" not in err, err
    assert space.resolve(case.expect) in lines[0], lines[0]
    ROWS[case.id] = (case.source, _shown(["ioc-bench", *case.argv]), exc.value.code, _shown([lines[0]], tmp_path))


def test_a_board_written_into_its_results_folder_is_not_read_back(tmp_path, make_result, capsys):
    """(Issue 12: ``leaderboard R --out R/board`` worked once, then read its own leaderboard.json.)"""
    root = make_results(tmp_path, "valid", make_result())
    for _ in range(2):
        assert main(["leaderboard", str(root), "--out", str(root / "board"), "--json"]) == 0
        cells = json.loads(capsys.readouterr().out)["cells"]
        assert sum(c["cases"] for c in cells) == 1
    ROWS["leaderboard-out-inside-results"] = (
        ISSUE,
        "ioc-bench leaderboard {res:valid} --out {res:valid}/board (twice)",
        0,
        "both runs summarise the 1 case; board/leaderboard.json is not a result file",
    )


# -- the Python API -------------------------------------------------------------------------------


def _run_cases_unknown_executor(tmp: Path):
    return runner.run_cases([CaseSpec("log-barrier", "nominal", "ideal", 0)], tmp / "out", executor="nope")


API_CASES: list[tuple[str, str, Callable[[Path, Path], object], type[Exception], str]] = [
    ("Demonstration.load (meta a list)", ISSUE, lambda t, g: Demonstration.load(make_demo(t, g, "meta-list")),
     DemonstrationFileError, "'meta' header must be a JSON object"),
    ("Demonstration.load (weights a list)", ISSUE, lambda t, g: Demonstration.load(make_demo(t, g, "weights-list")),
     DemonstrationFileError, "weights must be a JSON object"),
    ("Demonstration.load (0-d q)", ISSUE, lambda t, g: Demonstration.load(make_demo(t, g, "q-0d")),
     DemonstrationFileError, "array q has shape ()"),
    ("Demonstration.load (corrupted member)", ISSUE, lambda t, g: Demonstration.load(make_demo(t, g, "corrupted")),
     DemonstrationFileError, "not a readable .npz"),
    ("Demonstration.load (renamed .npy)", ISSUE, lambda t, g: Demonstration.load(make_demo(t, g, "renamed-npy")),
     DemonstrationFileError, "not a zip archive"),
    ('optimize_gait(task=0.27)', ISSUE, lambda t, g: optimize_gait(task=0.27),
     ValueError, "task must be a Task (e.g. Task(speed=0.27)), got float 0.27"),
    ('optimize_gait(init="x.npz")', ISSUE, lambda t, g: optimize_gait(init="x.npz"),
     ValueError, "init must be a Demonstration"),
    ("run_case(config=[1, 2])", ISSUE, lambda t, g: run_case(config=[1, 2]),
     ValueError, "an algorithm config must be a mapping"),
    ("Task(True)", ISSUE, lambda t, g: Task(True), ValueError, "speed must be a positive finite number, got True"),
    ("optimize_gait(workers=0)", ISSUE, lambda t, g: optimize_gait(workers=0),
     ValueError, "workers must be an integer >= 1 or None, got 0"),
    ('optimize_gait("1,2")', ISSUE, lambda t, g: optimize_gait("1,2"),
     ValueError, "expected 3 weights (hip, knee, dtau) or 6"),
    ('run_cases(executor="nope")', ISSUE, lambda t, g: _run_cases_unknown_executor(t),
     ValueError, "unknown executor 'nope'; valid: local, ray"),
    ("run_case(seed=-1)", ADDED, lambda t, g: run_case(seed=-1), ValueError, "seed must be a non-negative integer"),
    ('run_case(config={"n_random": "3"})', ADDED, lambda t, g: run_case(config={"n_random": "3"}),
     ValueError, "n_random must be an integer"),
    ("optimize_gait(seed=-1)", ADDED, lambda t, g: optimize_gait(seed=-1), ValueError, "non-negative integer"),
    ('CaseSpec("../x", ...)', ADDED, lambda t, g: CaseSpec("../x", "nominal", "ideal", 0),
     ValueError, "invalid algorithm name"),
    ('parse_weights({"hip": None})', ADDED, lambda t, g: ioc_bench.parse_weights({"hip": None}),
     ValueError, "weights must be numbers"),
]  # fmt: skip


@pytest.mark.parametrize(("name", "source", "call", "error", "expect"), API_CASES, ids=[c[0] for c in API_CASES])
def test_python_api_raises_one_documented_error(name, source, call, error, expect, tmp_path, good_demo, no_work):
    with pytest.raises(error) as exc:
        call(tmp_path, good_demo)
    message = str(exc.value)
    assert expect in message and "\n" not in message
    API_ROWS[name] = (source, type(exc.value).__name__, _shown([message], tmp_path))


# -- the table -----------------------------------------------------------------------------------


def _shown(parts: list[str], tmp: Path | None = None) -> str:
    text = " ".join(parts)
    if tmp is not None:
        text = text.replace(str(tmp), "<tmp>")
    return text.replace("|", "\\|")


#: Result handling (issue 12's last point): where each is shown.
RESULT_HANDLING = [
    ("a result of every config pooled into one leaderboard cell", "cells are (algorithm, config)",
     "tests/bench/test_leaderboard.py::test_configs_never_share_a_cell_and_the_header_names_each"),
    ("a config that only spells out defaults makes a second key", "configs are canonical before hashing",
     "tests/bench/test_results.py::test_a_config_spelling_out_defaults_is_the_same_case"),
    ("timeouts, dead workers and config errors are done forever",
     "failed cases are retried by default (--keep-failed keeps them); config errors are refused before work",
     "tests/bench/test_runner.py::test_timeouts_and_dead_workers_are_recorded_then_retried, "
     "::test_smoke_suite_killed_midway_resumes_and_retries_a_failed_case"),
    ("the Ray executor can overwrite a success just written with a failure",
     "one scheduler calls finish once per case; an error while recording stops the run",
     "tests/bench/test_runner.py::test_an_error_while_recording_a_success_stops_the_run_and_is_never_recorded_as_a_failure"),
    ("an algorithm name like ../x writes outside the results folder", "names are checked as folder names",
     "tests/ioc/test_registry.py::test_names_that_cannot_be_folder_names_are_refused, "
     "tests/bench/test_results.py::test_a_bad_case_is_refused_when_made"),
    ("leaderboard writes README.md then leaderboard.json", "both rendered, then written together",
     "tests/bench/test_leaderboard.py::test_the_two_files_are_written_together_or_not_at_all"),
    ("a writer killed mid-write leaves a tmp file", "unnamed (O_TMPFILE) staging; leftovers removed by the next run",
     "tests/test_fileio.py::test_sigkill_at_every_line_of_a_write_leaves_old_or_new_never_half"),
]  # fmt: skip


def render_table() -> str:
    lines = [
        "# Bad input: every input tried, its exit code and its message",
        "",
        "Generated by `IOC_BENCH_WRITE_DOCS=1 python -m pytest tests/cli/test_bad_input.py` (the test",
        "fails when this file is not current). `<tmp>` is the test's scratch folder; `{file}` a plain file,",
        "`{demo}` a good demonstration, `{demo:<kind>}` one spoilt that way and `{res:<kind>}` a results folder",
        "holding a bad result file of that kind (see the test). Every command line ran in-process with solving",
        "disabled, so none of them got to any expensive work.",
        "",
        f"## Command line ({len(ROWS)} inputs)",
        "",
        "| # | from | command | exit | message (stderr, one line) |",
        "|---|---|---|---|---|",
    ]
    order = [c.id for c in CASES] + ["leaderboard-out-inside-results"]
    for i, key in enumerate(order, 1):
        source, command, code, message = ROWS[key]
        lines.append(f"| {i} | {source} | `{command}` | {code} | {message} |")
    lines += [
        "",
        f"## Python API ({len(API_ROWS)} calls)",
        "",
        "| # | from | call | raises | message |",
        "|---|---|---|---|---|",
    ]
    for i, (name, *_rest) in enumerate(API_CASES, 1):
        source, error, message = API_ROWS[name]
        lines.append(f"| {i} | {source} | `{name}` | {error} | {message} |")
    lines += ["", "## Result handling", "", "| issue 12 said | now | shown by |", "|---|---|---|"]
    lines += [f"| {said} | {now} | `{test}` |" for said, now, test in RESULT_HANDLING]
    return "\n".join(lines) + "\n"


def test_the_table_in_docs_is_current():
    if len(ROWS) < len(CASES) + 1 or len(API_ROWS) < len(API_CASES):
        pytest.skip("only part of the table was run")
    text = render_table()
    if os.environ.get("IOC_BENCH_WRITE_DOCS"):
        DOC.write_text(text)
    assert DOC.is_file() and DOC.read_text() == text, (
        "docs/bad_input.md is out of date: IOC_BENCH_WRITE_DOCS=1 python -m pytest tests/cli/test_bad_input.py"
    )
