"""Every bad input exits with code 2 and one line, before any work: issue 12's list and more.

Each row of :data:`CASES` is a command line a user could type, with the files it needs
made in a fresh folder; the command must exit with the expected code, print exactly one
line on stderr (no traceback) and say what is wrong. :data:`API_CASES` does the same for
the Python API: one documented error type and a clear message. ``docs/bad_input.md`` is
the table of every input tried with its exit code and message; the last test checks it
is current, and ``IOC_BENCH_WRITE_DOCS=1 python -m pytest tests/cli/test_bad_input.py``
rewrites it.

Every command line also must leave its scratch folder as it found it and write nothing in
the current folder (nothing outside --out, no temporary left). Issue 24 (round 3) added
the classes: writes outside the output folder, result files that are not their case,
paths that pass a check and fail after the work, parsers, and Python API errors.
"""

from __future__ import annotations

import json
import os
import re
import stat
import zipfile
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pytest

import ioc_bench
from ioc_bench import Demonstration, DemonstrationFileError, Task, optimize_gait, run_case
from ioc_bench.bench import runner
from ioc_bench.bench.leaderboard import write_leaderboard
from ioc_bench.bench.results import (
    CaseSpec,
    ResultFileError,
    load_results,
    parse_result,
    read_result,
    results_directory,
    write_result,
)
from ioc_bench.cli import main
from ioc_bench.fileio import PathError, check_output_dir, read_bytes
from ioc_bench.viz.figures import make_figures

DOC = Path(__file__).resolve().parents[2] / "docs" / "bad_input.md"
ISSUE, ADDED, ROUND3 = "issue 12", "added", "issue 24"
#: Byte length of the ``{deep}`` path: over the 4095 a path may have, and the same on every machine
#: whatever the length of the scratch folder's name (the refusal message quotes it).
DEEP_PATH_BYTES = 4300


def _deep_path(tmp: Path, total: int = DEEP_PATH_BYTES) -> str:
    """A path of exactly ``total`` bytes under ``tmp``, in components of at most 200 bytes."""
    remaining = total - len(os.fsencode(str(tmp)))
    assert remaining > 402, "the scratch folder's name is too long for the deep path"
    sizes = [200] * (-(-remaining // 201))
    sizes[-1] = remaining - 201 * (len(sizes) - 1) - 1
    if sizes[-1] == 0:
        sizes[-2:] = [199, 1]
    path = str(tmp) + "".join("/" + "d" * n for n in reversed(sizes))  # the short one first: the tail is fixed
    assert len(os.fsencode(path)) == total
    return path


#: Text of very deep JSON and of a 100 KB config, resolved from ``{nested-json}`` and ``{huge-config}``.
NESTED_JSON = "[" * 100_000 + "]" * 100_000
HUGE_CONFIG = '{"n_random": [' + "1," * 50_000 + "1]}"


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
    "meta-nested": lambda a: a | {"meta": np.array('{"schema": 2, "gait": ' + NESTED_JSON + "}")},
    "n-intervals-huge": lambda a: _with_meta(a, n_intervals=10**30),
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
    elif kind == "long-stem":  # the file's name is fine; "<stem>_replay.png" would not be
        path = tmp / f"{'d' * 250}.npz"
        path.write_bytes(good.read_bytes())
    elif kind == "fifo":
        path = tmp / "fifo.npz"
        os.mkfifo(path)
    else:
        raise KeyError(kind)
    return path


def make_results(tmp: Path, kind: str, make_result) -> Path:
    """A results folder: ``valid`` (one good result) or one with a bad file of ``kind``.

    The file is always ``log-barrier/nominal__ideal__seed0.json``; its content, or what it
    is (a link, a FIFO, a folder), is spoilt as ``kind`` says.
    """
    root = tmp / f"results-{kind}"
    if kind == "missing":
        return root
    root.mkdir()
    if kind == "empty":
        return root
    if kind == "linked-folder":  # the algorithm's folder is a link to a folder outside the results
        (tmp / "outside").mkdir()
        (root / "log-barrier").symlink_to(tmp / "outside")
        return root
    result = make_result()
    path = write_result(root, CaseSpec("log-barrier", "nominal", "ideal", 0), result)
    data = path.read_text() and json.loads(path.read_text())
    if kind in RESULT_NODES:
        path.unlink()
        RESULT_NODES[kind](path)
        return root
    bad = {
        "valid": None,
        "null": "null",
        "list": "[1, 2]",
        "wall-time": data | {"wall_time": "fast"},
        "weights-2": data | {"weights": [0.5, 0.5]},
        "unknown-field": data | {"surprise": 1},
        "not-json": "{not json",
        # issue 24: files whose content is not their case, or out of range
        "escaping-algorithm": data | {"algorithm": "x/../../ESCAPED"},
        "other-algorithm": make_result(algorithm="analytic-center").to_dict(),
        "other-seed": data | {"seed": 1},
        "other-config": make_result(config={"n_random": 3}).to_dict(),
        "case-key-other": data | {"case_key": "log-barrier/nominal__ideal__seed1"},
        "unknown-condition": data | {"condition": "nope"},
        "unknown-weight-set": data | {"weight_set": "nope"},
        "duplicate-features": data | {"features": ["hip", "hip", "dtau"]},
        "unknown-feature": data | {"features": ["hip", "knee", "bogus"]},
        "negative-error": data | {"weight_error": -0.5},
        "negative-time": data | {"wall_time": -1.0},
        "zero-truth": data | {"true_weights": [0.0, 0.0, 0.0]},
        "wrong-truth": data | {"true_weights": [0.099, 0.990, 0.099]},
        "huge-n-solves": data | {"n_solves": 10**30},
        "multiline-status": data | {"status": "converged\nFAKE"},
        "nested": '{"notes": ' + NESTED_JSON + "}",
    }[kind]
    if bad is not None:
        path.write_text(bad if isinstance(bad, str) else json.dumps(bad))
    return root


#: Result files that are not regular files: made in place of a good one.
RESULT_NODES: dict[str, Callable[[Path], None]] = {
    "link-passwd": lambda p: p.symlink_to("/etc/passwd"),
    "link-zero": lambda p: p.symlink_to("/dev/zero"),
    "fifo": lambda p: os.mkfifo(p),
    "directory": lambda p: p.mkdir(),
}


@dataclass(frozen=True)
class Case:
    """One command line; ``{tmp}``, ``{file}``, ``{demo}``, ``{demo:<kind>}``, ``{res:<kind>}`` are made
    (and the other tokens of :meth:`Workspace.resolve`)."""

    id: str
    source: str
    argv: tuple[str, ...]
    expect: str
    code: int = 2
    hold: str = ""  # a results folder another run holds while this one starts
    cache: str = ""  # IOC_BENCH_CACHE for this command line (a token), if set


def C(id: str, source: str, line: str, expect: str, code: int = 2, hold: str = "", cache: str = "") -> Case:
    return Case(id, source, tuple(line.split()), expect, code, hold, cache)


CASES: list[Case] = [
    # tracebacks
    C("ioc-config-negative", ISSUE, 'ioc --config {"n_random":-1}', "n_random must be >= 0"),
    C("ioc-config-choice", ISSUE, 'ioc --config {"forward_start":"nope"}', "forward_start must be 'warm' or 'cold'"),
    C("ioc-seed-negative", ISSUE, "ioc --seed -1", "must be >= 0"),
    C("gait-seed-negative", ISSUE, "gait --seed -1", "must be >= 0"),
    C("ioc-out-under-file", ISSUE, "ioc --out {file}/r.json", "/file/r.json: /"),
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
    # issue 24, security: nothing written or read outside the folders given
    C("figures-escaping-algorithm", ROUND3, "figures {res:escaping-algorithm} --out {tmp}/figs",
      "invalid algorithm name 'x/../../ESCAPED'"),
    C("run-linked-algorithm-folder", ROUND3, "run --out {res:linked-folder}", "leads out of"),
    C("leaderboard-result-link-passwd", ROUND3, "leaderboard {res:link-passwd}", "is a symbolic link"),
    C("leaderboard-result-link-zero", ROUND3, "leaderboard {res:link-zero}", "is a symbolic link"),
    C("leaderboard-result-fifo", ROUND3, "leaderboard {res:fifo}", "is a FIFO, not a regular file"),
    C("figures-result-directory", ROUND3, "figures {res:directory} --out {tmp}/figs", "is a directory"),
    C("run-result-fifo", ROUND3, "run --out {res:fifo}", "is a FIFO"),
    C("leaderboard-out-empty", ROUND3, "leaderboard {res:valid} --out {empty}", "empty string"),
    C("leaderboard-readme-a-folder", ROUND3, "leaderboard {res:valid} --out {readme-dir}",
      "README.md is a directory"),
    C("replay-dev-zero", ROUND3, "replay /dev/zero", "under /dev"),
    C("replay-fifo", ROUND3, "replay {demo:fifo}", "is a FIFO"),
    C("replay-passwd", ROUND3, "replay /etc/passwd", "not a zip archive"),
    # issue 24, result files are not trusted
    C("leaderboard-other-algorithm", ROUND3, "leaderboard {res:other-algorithm}",
      "holds the case analytic-center/nominal__ideal__seed0, not the one its name says"),
    C("run-other-algorithm-not-done", ROUND3, "run --out {res:other-algorithm}", "holds the case analytic-center/"),
    C("leaderboard-other-seed", ROUND3, "leaderboard {res:other-seed}",
      "holds the case log-barrier/nominal__ideal__seed1"),
    C("run-other-config-not-done", ROUND3, "run --out {res:other-config}",
      "holds the case log-barrier/nominal__ideal__seed0__cfg"),
    C("leaderboard-case-key-other", ROUND3, "leaderboard {res:case-key-other}", "records case_key"),
    C("leaderboard-unknown-condition", ROUND3, "leaderboard {res:unknown-condition}", "unknown condition 'nope'"),
    C("leaderboard-unknown-weight-set", ROUND3, "leaderboard {res:unknown-weight-set}", "unknown weight set 'nope'"),
    C("leaderboard-duplicate-features", ROUND3, "leaderboard {res:duplicate-features}", "distinct known features"),
    C("figures-unknown-feature", ROUND3, "figures {res:unknown-feature} --out {tmp}/figs", "distinct known features"),
    C("leaderboard-negative-error", ROUND3, "leaderboard {res:negative-error}",
      "weight_error must be a number from 0 to 1"),
    C("leaderboard-negative-time", ROUND3, "leaderboard {res:negative-time}", "wall_time must be a number from 0 to"),
    C("leaderboard-zero-truth", ROUND3, "leaderboard {res:zero-truth}", "true_weights [0.0, 0.0, 0.0] are not"),
    C("leaderboard-wrong-truth", ROUND3, "leaderboard {res:wrong-truth}", "are not the truth of weight set 'nominal'"),
    C("leaderboard-huge-n-solves", ROUND3, "leaderboard {res:huge-n-solves}", "n_solves must be between 0 and"),
    C("leaderboard-multiline-status", ROUND3, "leaderboard {res:multiline-status}", "status must be one line of 1 to"),
    C("leaderboard-nested-result", ROUND3, "leaderboard {res:nested}", "JSON nested deeper than 64 levels"),
    # issue 24, paths that passed the check and failed after the work
    C("gait-out-empty", ROUND3, "gait --out {empty}", "empty string"),
    C("ioc-out-empty", ROUND3, "ioc --out {empty}", "empty string"),
    C("run-out-empty", ROUND3, "run --out {empty}", "empty string"),
    C("replay-out-empty", ROUND3, "replay {demo} --out {empty}", "empty string"),
    C("figures-out-empty", ROUND3, "figures {res:valid} --out {empty}", "empty string"),
    C("gait-out-proc", ROUND3, "gait --out /proc/demo.npz", "under /proc"),
    C("ioc-out-sys", ROUND3, "ioc --out /sys/ioc_result.json", "under /sys"),
    C("run-out-proc", ROUND3, "run --out /proc/results", "under /proc"),
    C("replay-out-sys", ROUND3, "replay {demo} --out /sys/replays", "under /sys"),
    C("leaderboard-out-proc", ROUND3, "leaderboard {res:valid} --out /proc/board", "under /proc"),
    C("figures-out-dev", ROUND3, "figures {res:valid} --out /dev/figs", "under /dev"),
    C("gait-out-loop", ROUND3, "gait --out {loop}/demo.npz", "symbolic link loop"),
    C("ioc-out-loop", ROUND3, "ioc --out {loop}", "symbolic link loop"),
    C("run-out-loop", ROUND3, "run --out {loop}/results", "symbolic link loop"),
    C("leaderboard-out-loop", ROUND3, "leaderboard {res:valid} --out {loop}", "symbolic link loop"),
    C("figures-out-dangling", ROUND3, "figures {res:valid} --out {dangling}", "a symbolic link to nothing"),
    C("gait-out-long-name", ROUND3, "gait --out {tmp}/{long}.npz", "over the 255 a file name may have"),
    C("ioc-out-long-name", ROUND3, "ioc --out {tmp}/{long}.json", "over the 255 a file name may have"),
    C("run-out-long-name", ROUND3, "run --out {tmp}/{long}", "over the 255 a file name may have"),
    C("replay-out-long-name", ROUND3, "replay {demo} --out {tmp}/{long}", "over the 255 a file name may have"),
    C("replay-output-name-too-long", ROUND3, "replay {demo:long-stem}", "over the 255 a file name may have"),
    C("leaderboard-out-long-path", ROUND3, "leaderboard {res:valid} --out {deep}", "over the 4095 a path may have"),
    C("gait-out-fifo", ROUND3, "gait --out {fifo}.npz", "is a FIFO, not a regular file"),
    C("ioc-out-device", ROUND3, "ioc --out /dev/null", "under /dev"),
    C("ioc-cache-a-file", ROUND3, "ioc", "/file/demos: /", cache="{file}"),
    C("run-cache-a-file", ROUND3, "run --out {tmp}/results", "demonstration cache", cache="{file}"),
    C("run-cache-empty", ROUND3, "run --out {tmp}/results", "IOC_BENCH_CACHE is set but empty", cache="{empty}"),
    C("ioc-cache-proc", ROUND3, "ioc --out {tmp}/r.json", "under /proc", cache="/proc/cache"),
    # issue 24, parsers
    C("ioc-config-nested", ROUND3, "ioc --config {nested-json}", "JSON nested deeper than 64 levels"),
    C("run-config-nested", ROUND3, "run --config {nested-json}", "JSON nested deeper than 64 levels"),
    C("ioc-config-huge-text", ROUND3, "ioc --config {huge-config}", "n_random must be an integer, got [1, 1,"),
    C("ioc-config-huge-int", ROUND3, 'ioc --config {"n_random":100000000000000000000000}',
      "n_random must be an integer within ±2147483647"),
    C("ioc-config-1e23", ROUND3, 'ioc --config {"n_random":1e23}', "n_random must be an integer"),
    C("ioc-config-int-beyond-float", ROUND3, "ioc --config {huge-int-config}", "perturbation must be a finite number"),
    C("replay-meta-nested", ROUND3, "replay {demo:meta-nested}", "'meta' header is JSON nested deeper than 64 levels"),
    C("replay-n-intervals-huge", ROUND3, "replay {demo:n-intervals-huge}", "n_intervals must be an integer from 0"),
    C("run-list-unknown-suite", ROUND3, "run --list --suite nope --json", "unknown suite 'nope'"),
]  # fmt: skip


@pytest.fixture(scope="module")
def good_demo(nominal_demo, tmp_path_factory) -> Path:
    return nominal_demo.save(tmp_path_factory.mktemp("good") / "good.npz")


#: Length of every scratch folder's path here: messages shorten deep paths and cut long lines at
#: fixed lengths, so the table reads the same whatever the length of pytest's temporary folder.
SCRATCH_PATH_CHARS = 240
#: What pads a scratch folder's path to that length (no letter the table's placeholders use).
PAD = "w"


def _fixed_length(tmp: Path) -> Path:
    """A new folder under ``tmp`` whose path has :data:`SCRATCH_PATH_CHARS` characters."""
    room = SCRATCH_PATH_CHARS - len(str(tmp)) - 1
    assert room >= 100, f"pytest's temporary folder {tmp} is too deep for this test's fixed-length scratch"
    folder = tmp / (PAD * room)
    folder.mkdir()
    return folder


class Workspace:
    """Makes the files a command line names, in one folder."""

    def __init__(self, tmp: Path, good_demo: Path, make_result):
        self.tmp, self.good_demo, self.make_result = tmp, good_demo, make_result
        (tmp / "file").write_text("a plain file")
        (tmp / "dir.npz").mkdir()

    def resolve(self, token: str) -> str:
        """``token`` with every ``{...}`` replaced by what it names (made if needed)."""
        fixed = {
            "{tmp}": str(self.tmp),
            "{file}": str(self.tmp / "file"),
            "{empty}": "",
            "{long}": "n" * 256,
            "{nested-json}": NESTED_JSON,
            "{huge-config}": HUGE_CONFIG,
            "{huge-int-config}": '{"perturbation": 1' + "0" * 400 + "}",
        }
        for key, value in fixed.items():
            token = token.replace(key, value)
        for name, make in (("{loop}", self._loop), ("{dangling}", self._dangling), ("{fifo}", self._fifo)):
            if name in token:
                token = token.replace(name, str(make()))
        if "{readme-dir}" in token:
            (self.tmp / "board" / "README.md").mkdir(parents=True, exist_ok=True)
            token = token.replace("{readme-dir}", str(self.tmp / "board"))
        if "{deep}" in token:
            token = token.replace("{deep}", _deep_path(self.tmp))
        while "{demo" in token or "{res:" in token:
            start = token.index("{")
            end = token.index("}", start)
            name = token[start + 1 : end]
            if name == "demo":
                value = self.good_demo
            elif name.startswith("demo:"):
                value = make_demo(self.tmp, self.good_demo, name[5:])
            else:
                value = self._made(name) or make_results(self.tmp, name[4:], self.make_result)
            token = token[:start] + str(value) + token[end + 1 :]
        return token

    def _made(self, name: str) -> Path | None:
        path = self.tmp / f"results-{name[4:]}"
        return path if path.exists() or path.is_symlink() else None

    def _loop(self) -> Path:
        path = self.tmp / "loop"
        if not path.is_symlink():
            path.symlink_to(path)
        return path

    def _dangling(self) -> Path:
        path = self.tmp / "dangling"
        if not path.is_symlink():
            path.symlink_to(self.tmp / "nothing-here")
        return path

    def _fifo(self) -> Path:
        path = self.tmp / "fifo"
        if not path.exists():
            os.mkfifo(path)
            os.mkfifo(path.with_suffix(".npz"))
        return path

    def snapshot(self) -> dict[str, tuple]:
        """Every name under the folder with its kind, size and time: what a refused command must not change."""
        found = {}
        for folder, dirs, names in os.walk(self.tmp):
            for name in dirs + names:
                st = os.lstat(Path(folder) / name)
                found[str(Path(folder) / name)] = (stat.S_IFMT(st.st_mode), st.st_size, st.st_mtime_ns)
        return found


ROWS: dict[str, tuple[str, str, int, str]] = {}
API_ROWS: dict[str, tuple[str, str, str]] = {}


@pytest.fixture
def no_work(monkeypatch):
    """Fail the test if any command gets as far as solving something."""

    def forbidden(*args, **kwargs):
        raise AssertionError("expensive work started before the input was checked")

    from ioc_bench.trajopt.forward_problem import ForwardProblem

    monkeypatch.setattr(runner, "prepare_inputs", forbidden)
    monkeypatch.setattr(ForwardProblem, "solve", forbidden)  # every solve, whoever asks
    monkeypatch.setattr(ForwardProblem, "__init__", forbidden)  # and every build


#: Longest stderr line a refusal may print (cut in the middle beyond this).
MAX_LINE = 400 + len("ioc-bench leaderboard: error: ")


@pytest.mark.parametrize("case", CASES, ids=[c.id for c in CASES])
def test_bad_input_exits_2_with_one_line(case: Case, tmp_path, good_demo, make_result, capsys, no_work, monkeypatch):
    space = Workspace(_fixed_length(tmp_path), good_demo, make_result)
    argv = [space.resolve(a) for a in case.argv]
    hold = space.resolve(case.hold) if case.hold else None
    if case.cache:
        monkeypatch.setenv("IOC_BENCH_CACHE", space.resolve(case.cache))
    cwd = tmp_path.parent / f"{tmp_path.name}-cwd"
    cwd.mkdir()
    monkeypatch.chdir(cwd)
    before = space.snapshot()
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
    assert len(lines[0]) <= MAX_LINE, f"a {len(lines[0])}-character line"
    assert space.snapshot() == before, "a refused command changed its folder"
    assert not any(cwd.iterdir()), f"written in the current folder: {list(cwd.iterdir())}"
    shown_line = _shown([lines[0]], space.tmp).replace("n" * 256, "{long}").replace("d" * 200, "{d200}")
    env = [f"IOC_BENCH_CACHE={case.cache or chr(39) * 2}"] if case.cache else []
    ROWS[case.id] = (case.source, _shown([*env, "ioc-bench", *case.argv]), exc.value.code, shown_line)


def test_a_board_written_into_its_results_folder_is_not_read_back(tmp_path, make_result, capsys):
    """(Issue 12: ``leaderboard R --out R/board`` worked once, then read its own leaderboard.json.)"""
    root = make_results(tmp_path, "valid", make_result)
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


def _run_cases_into(out: str):
    return runner.run_cases([CaseSpec("log-barrier", "nominal", "ideal", 0)], out)


def _results(tmp: Path, kind: str) -> Path:
    return make_results(tmp, kind, _SYNTHETIC[0])


#: The conftest's ``synthetic_result`` (a fixture gives it; API calls take only (tmp, demo)).
_SYNTHETIC: list[Callable] = []


def _board_into_readme_folder(tmp: Path):
    results = load_results(make_results(tmp, "valid", _SYNTHETIC[0]))
    (tmp / "board" / "README.md").mkdir(parents=True)
    return write_leaderboard(results, tmp / "board")


def _fifo(tmp: Path, name: str) -> Path:
    os.mkfifo(tmp / name)
    return tmp / name


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
    # issue 24
    ("Task(10**400)", ROUND3, lambda t, g: Task(10**400),
     ValueError, "speed must be a positive finite number, got an integer of about 401 digits"),
    ("Task(0.27, step_length=np.inf)", ROUND3, lambda t, g: Task(0.27, step_length=np.inf),
     ValueError, "step_length must be a positive finite number"),
    ("Demonstration.load(None)", ROUND3, lambda t, g: Demonstration.load(None),
     DemonstrationFileError, "path must be a demonstration file's path (str or os.PathLike), got NoneType"),
    ("Demonstration.load(5)", ROUND3, lambda t, g: Demonstration.load(5), DemonstrationFileError, "got int"),
    ('Demonstration.load("")', ROUND3, lambda t, g: Demonstration.load(""), DemonstrationFileError, "empty string"),
    ('Demonstration.load("/dev/zero")', ROUND3, lambda t, g: Demonstration.load("/dev/zero"),
     DemonstrationFileError, "under /dev"),
    ("Demonstration.load (a FIFO)", ROUND3, lambda t, g: Demonstration.load(_fifo(t, "demo.npz")),
     DemonstrationFileError, "is a FIFO, not a regular file"),
    ("Demonstration.load (meta nested 100000 deep)", ROUND3,
     lambda t, g: Demonstration.load(make_demo(t, g, "meta-nested")),
     DemonstrationFileError, "'meta' header is JSON nested deeper than 64 levels"),
    ('Demonstration.save("/proc/demo.npz")', ROUND3, lambda t, g: Demonstration.load(g).save("/proc/demo.npz"),
     PathError, "under /proc"),
    ('run_case(weights="penalize-knee", demo=<a nominal demonstration>)', ROUND3,
     lambda t, g: run_case(weights="penalize-knee", demo=Demonstration.load(g)),
     ValueError, "demo was made with weights"),
    ('optimize_gait(params="walker")', ROUND3, lambda t, g: optimize_gait(params="walker"),
     ValueError, "params must be a WalkerParams (e.g. WalkerParams()), got str 'walker'"),
    ('optimize_gait(model="walker")', ROUND3, lambda t, g: optimize_gait(model="walker"),
     ValueError, "model must be a GaitModel"),
    ('optimize_gait(rules="paper")', ROUND3, lambda t, g: optimize_gait(rules="paper"),
     ValueError, "rules must be a StepRules"),
    ('optimize_gait(guesses="demo.npz")', ROUND3, lambda t, g: optimize_gait(guesses="demo.npz"),
     ValueError, "guesses must be a list of Demonstrations"),
    ('optimize_gait(guesses=["demo.npz"])', ROUND3, lambda t, g: optimize_gait(guesses=["demo.npz"]),
     ValueError, "each of guesses must be a Demonstration"),
    ("optimize_gait(starts=10**9)", ROUND3, lambda t, g: optimize_gait(starts=10**9),
     ValueError, "starts must be at most 10000"),
    ("read_result (a FIFO)", ROUND3, lambda t, g: read_result(_fifo(t, "nominal__ideal__seed0.json")),
     ResultFileError, "is a FIFO, not a regular file"),
    ("load_results (another algorithm's result under log-barrier/)", ROUND3,
     lambda t, g: load_results(_results(t, "other-algorithm")),
     ResultFileError, "holds the case analytic-center/nominal__ideal__seed0"),
    ("parse_result (n_solves 10**30)", ROUND3,
     lambda t, g: parse_result(_SYNTHETIC[0]().to_dict() | {"n_solves": 10**30}),
     ValueError, "n_solves must be between 0 and 1000000000"),
    ("write_result (algorithm folder a link out)", ROUND3,
     lambda t, g: write_result(_results(t, "linked-folder"), CaseSpec("log-barrier", "nominal", "ideal", 0),
                               _SYNTHETIC[0]()),
     ResultFileError, "leads out of"),
    ('run_cases(out="")', ROUND3, lambda t, g: _run_cases_into(""), PathError, "empty string"),
    ('run_cases(out="/proc/results")', ROUND3, lambda t, g: _run_cases_into("/proc/results"),
     PathError, "under /proc"),
    ("make_figures (algorithm x/../../ESCAPED)", ROUND3,
     lambda t, g: make_figures(_results(t, "escaping-algorithm"), t / "figs"),
     ResultFileError, "invalid algorithm name 'x/../../ESCAPED'"),
    ('make_figures(out_dir="")', ROUND3, lambda t, g: make_figures(_results(t, "valid"), ""),
     PathError, "empty string"),
    ("write_leaderboard (README.md a folder)", ROUND3, lambda t, g: _board_into_readme_folder(t),
     PathError, "README.md is a directory"),
    ('check_output_dir("/sys/x")', ROUND3, lambda t, g: check_output_dir("/sys/x"), PathError, "under /sys"),
    ('read_bytes("/dev/zero", 10)', ROUND3, lambda t, g: read_bytes("/dev/zero", 10), PathError, "under /dev"),
]  # fmt: skip


@pytest.mark.parametrize(("name", "source", "call", "error", "expect"), API_CASES, ids=[c[0] for c in API_CASES])
def test_python_api_raises_one_documented_error(
    name, source, call, error, expect, tmp_path, good_demo, no_work, make_result
):
    _SYNTHETIC[:] = [make_result]
    scratch = _fixed_length(tmp_path)
    with pytest.raises(error) as exc:
        call(scratch, good_demo)
    message = str(exc.value)
    assert expect in message and "\n" not in message
    API_ROWS[name] = (source, type(exc.value).__name__, _shown([message], scratch))


# -- the table -----------------------------------------------------------------------------------


def _shown(parts: list[str], tmp: Path | None = None) -> str:
    text = " ".join(parts)
    if tmp is not None:
        text = re.sub(r"'/[^'\s]*?\.\.\.", "'<tmp>...", text)  # a quoted path cut to its ends is the scratch's
        text = re.sub(r"/\S*?\.\.\.", "<tmp>...", text)  # a deep path shortened to its ends starts in the scratch
        text = re.sub(rf"<tmp>\.\.\.{PAD}+", "<tmp>", text)  # and its end holds the scratch's padding
        text = text.replace(str(tmp), "<tmp>")
        text = re.sub(r"/\S*?pytest-\d+/[^/'\s.]*", "<tmp>", text)  # a scratch path cut short in a message
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


#: Issue 24 (round 3), by class: what it found, what holds now, and where that is shown
#: (besides the rows above marked "issue 24").
ROUND3_HANDLING = [
    ("figures wrote a PNG outside --out for a result whose algorithm is x/../../ESCAPED",
     "a result's algorithm must be a valid name; figure file names are built from checked names only",
     "tests/viz/test_figures.py::test_output_names_come_from_checked_identifiers_only"),
    ("run followed a linked algorithm folder inside --out and wrote outside it",
     "every case's folder must resolve inside --out: checked for every case before the run, again before each write",
     "tests/bench/test_results.py::test_a_case_folder_leading_out_of_the_results_is_refused_before_and_at_writing"),
    ("readers followed links named like results (/etc/passwd, /dev/zero), a FIFO blocked leaderboard forever",
     "result files are opened without following links and without blocking, checked to be regular files on the "
     "open descriptor, at most 32 MiB read",
     "tests/test_fileio.py::test_read_bytes_opens_regular_files_only_within_a_limit, "
     "tests/test_hostile_inputs.py::test_property_a_hostile_input_path_is_refused_without_blocking"),
    ("leaderboard --out '' wrote into the current folder; replay left MUJOCO_LOG.TXT there",
     "every path argument is parsed by one type that refuses ''; MuJoCo warnings go to stderr",
     "tests/cli/test_replay_cli.py::test_mujoco_warnings_go_to_stderr_not_to_a_log_file"),
    ("one algorithm's results filed under another's names were taken as done, and mixed in the leaderboard; "
     "a case in several files was counted several times",
     "a file's content must be the case its name says (every CaseSpec field compared through the key), so one "
     "case has one file; run refuses a file that is not its own case",
     "tests/bench/test_results.py::test_stored_result_is_never_another_case, "
     "tests/test_hostile_inputs.py::test_property_a_record_under_another_case_name_is_refused"),
    ("another algorithm, unknown condition or weight set, duplicate or unknown features, negative errors or times, "
     "zero true weights were rendered as valid; n_solves 10**30 ended in a traceback",
     "every field typed and in range, the true weights the weight set's",
     "tests/bench/test_results.py::test_out_of_range_values_are_refused, "
     "tests/test_hostile_inputs.py::test_property_a_spoilt_record_is_refused_with_one_line_naming_the_file"),
    ("run_case(demo=<penalize-knee demonstration>, weights='nominal') scores against the wrong truth",
     "refused by the one case pipeline (the lead's bench/case.py): a demonstration of another case is a ValueError",
     "the API row run_case(weights=\"penalize-knee\", demo=...) above"),
    ("outputs under /proc or /sys, through a link loop, with a 256-byte name, or '' passed the check "
     "(os.access says yes as root) and failed after the solve",
     "one policy (ioc_bench.fileio) for every command and the API, writability probed by making an unnamed file",
     "tests/test_fileio.py::test_output_dirs_that_would_fail_after_the_work_are_refused, "
     "tests/test_hostile_inputs.py::test_property_every_command_refuses_a_hostile_path_before_any_work"),
    ("IOC_BENCH_CACHE naming a file failed after 26 s", "the cache folder is checked before the work (ioc, run)",
     "rows ioc-cache-a-file, run-cache-a-file above"),
    ("README.md being a folder in the leaderboard's --out left a temporary file",
     "refused up front; atomic_write_many removes every staged temporary when a rename fails",
     "tests/test_fileio.py::test_atomic_write_many_leaves_no_temporary_when_a_rename_fails"),
    ("deep JSON raised RecursionError; a 100 KB config was echoed whole; n_random 1e23 was accepted",
     "JSON from outside is read at most 64 levels deep; messages are cut to 400 characters; ints are ints, "
     "config ints within a C int",
     "tests/test_hostile_inputs.py::test_property_json_of_any_depth_is_a_value_or_a_value_error"),
    ("run --list --suite nope --json ignored both; an unknown algorithm listed refused plugins; a plugin named "
     "like a built-in was ignored silently",
     "--list honours both; only algorithms that load are listed; the clash is reported as 'name clash refused'",
     "tests/cli/test_plugins_cli.py"),
    ("Task(10**400) raised OverflowError; Task(np.float32(0.27)) was refused",
     "every positive finite real is a speed (NumPy scalars at their own precision's decimal), the rest a ValueError",
     "tests/test_hostile_inputs.py::test_property_task_takes_every_positive_finite_real"),
    ("the differentiable view, IOCProblem.optimize(starts=10**9), gym.make(..., demonstration=5), "
     "reset(options=5), NaN reward settings",
     "not in this table: the lead's (ioc/) and the environment's (envs/) own checks", "-"),
]  # fmt: skip

#: The one error type each public entry point raises for bad input (every one a ``ValueError``).
ENTRY_POINT_ERRORS = [
    ("Task(speed, step_length)", "ValueError", "naming speed or step_length"),
    ("parse_weights(spec, features)", "ValueError", ""),
    ("optimize_gait(...)", "ValueError", "naming the argument; before any solve"),
    ("Demonstration.load(path)", "DemonstrationFileError", "for a bad path too (None, a folder, FIFO, device)"),
    ("Demonstration.save(path)", "ValueError", "PathError; before writing"),
    ("get_algorithm / make_algorithm / canonical_config", "AlgorithmError", "unknown name, bad config"),
    ("run_case(...)", "ValueError", "AlgorithmError for the algorithm and its config"),
    ("CaseSpec(...)", "ValueError", "AlgorithmError for the name and config"),
    ("plan_run / run_cases(specs, out, ...)", "ValueError",
     "PathError for out, ResultFileError for the files already there; before any work"),
    ("read_result / load_results / stored_result / write_result", "ResultFileError", "naming the file"),
    ("parse_result(data)", "ValueError", "naming the field"),
    ("write_leaderboard(results, out)", "ValueError", "PathError for out and its two files; before writing"),
    ("make_figures(results_dir, out_dir)", "ValueError",
     "ResultFileError for the results, PathError for out_dir and each file; before drawing"),
    ("fileio.check_* / read_bytes / check_inside / check_name", "PathError", ""),
]  # fmt: skip


def render_table() -> str:
    lines = [
        "# Bad input: every input tried, its exit code and its message",
        "",
        "Generated by `IOC_BENCH_WRITE_DOCS=1 python -m pytest tests/cli/test_bad_input.py` (the test",
        "fails when this file is not current). `<tmp>` is the test's scratch folder; `{file}` a plain file,",
        "`{demo}` a good demonstration, `{demo:<kind>}` one spoilt that way and `{res:<kind>}` a results folder",
        "holding a bad result file of that kind (see the test); `{empty}` is the empty string, `{long}` a name of",
        "256 bytes, `{loop}` a link to itself, `{dangling}` a link to nothing, `{deep}` a path of 4,300 bytes,",
        "`{nested-json}` 100,000 nested brackets, `{huge-config}` a 100 KB config. Every command line ran in-process",
        "with solving disabled, so none of them got to any expensive work; each one also left its scratch folder",
        "as it was and wrote nothing in the current folder (no file outside --out, no temporary left).",
        "",
        "What a path may be is decided in one place, `ioc_bench.fileio`, for every command and the API: not empty,",
        "no NUL, names of at most 255 bytes and paths of at most 4095, no link loop or link to nothing, not under a",
        "kernel pseudo-file system (/proc, /sys, /dev, or any proc/sysfs/devtmpfs/cgroup... mount; /dev/shm is",
        "allowed), a folder one can write in (tried by making an unnamed file: as root `os.access` says yes to",
        "everything) or a regular file to read (never a FIFO, device or folder; opened without blocking and at",
        "most a size limit read). Paths inside a tree (result files under --out) must not lead out of it.",
        "A result file must be a regular file inside its folder, every field typed and in range, and the case",
        "its name says. `python studies/bad_input_sweep.py` tries some 600 more inputs of these classes, generated,",
        "and counts how many are handled this way.",
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
    lines += ["", "## Round 3 (issue 24), by class", "", "| issue 24 said | now | shown by |", "|---|---|---|"]
    lines += [f"| {said} | {now} | {_code(test)} |" for said, now, test in ROUND3_HANDLING]
    lines += [
        "",
        "## The error each Python entry point raises for bad input",
        "",
        "Every one is a `ValueError` (or a subclass), raised before any expensive work, with a one-line message.",
        "",
        "| entry point | raises | note |",
        "|---|---|---|",
    ]
    lines += [f"| `{entry}` | `{error}` | {note} |" for entry, error, note in ENTRY_POINT_ERRORS]
    return "\n".join(lines) + "\n"


def _code(text: str) -> str:
    return text if text == "-" or text.startswith(("rows ", "the API row")) else f"`{text}`"


def test_the_table_in_docs_is_current():
    if len(ROWS) < len(CASES) + 1 or len(API_ROWS) < len(API_CASES):
        pytest.skip("only part of the table was run")
    text = render_table()
    if os.environ.get("IOC_BENCH_WRITE_DOCS"):
        DOC.write_text(text)
    assert DOC.is_file() and DOC.read_text() == text, (
        "docs/bad_input.md is out of date: IOC_BENCH_WRITE_DOCS=1 python -m pytest tests/cli/test_bad_input.py"
    )
