"""Every bad input exits with code 2 and one line, before any work.

Each row of :data:`CASES` is a command line a user could type, with the files it needs
made in a fresh folder; the command must exit with the expected code, print exactly one
line on stderr (no traceback) and say what is wrong. :data:`API_CASES` does the same for
the Python API: one documented error type and a clear message. ``docs/bad_input.md`` is
the table of every input tried with its exit code and message; the last test checks it
is current, and ``IOC_BENCH_WRITE_DOCS=1 python -m pytest tests/cli/test_bad_input.py``
rewrites it.

Every command line also must leave its scratch folder as it found it and write nothing in
the current folder (nothing outside --out, no temporary left). Rows are grouped by the
class of input they try (arguments, configs, names, output paths, demonstration files,
result files, the demonstration cache, the Ray cluster); the table's "input" column says
which.
"""

from __future__ import annotations

import json
import os
import re
import shutil
import stat
import tempfile
import zipfile
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pytest

import ioc_bench
from ioc_bench import Demonstration, DemonstrationFileError, Task, optimize_gait, run_case
from ioc_bench.cli import main
from ioc_bench.paths import PathError, check_output_dir, read_bytes
from ioc_bench.runner import run as runner
from ioc_bench.runner.leaderboard import write_leaderboard
from ioc_bench.runner.results import ResultFileError, load_results, read_result, results_directory, write_result
from ioc_bench.synthetic.case import CaseSpec
from ioc_bench.synthetic.results import parse_result
from ioc_bench.viz.figures import make_figures

DOC = Path(__file__).resolve().parents[2] / "docs" / "bad_input.md"
#: The class of input each row tries (the table's "input" column).
ARGUMENT, CONFIG, NAME, OUTPUT = "argument", "config", "name", "output path"
DEMO, RESULT, INPUT, CACHE, CLUSTER = (
    "demonstration file",
    "result file",
    "input file",
    "demonstration cache",
    "Ray cluster",
)
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
    if kind == "other-case":  # a good result of another case than ``valid``'s: seed 1
        write_result(root, CaseSpec("log-barrier", "nominal", "ideal", 1), make_result(seed=1))
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
        # files whose content is not their case, or out of range
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
    # arguments: numbers and options out of range
    C("ioc-seed-negative", ARGUMENT, "ioc --seed -1", "must be >= 0"),
    C("gait-seed-negative", ARGUMENT, "gait --seed -1", "must be >= 0"),
    C("gait-weights-inf", ARGUMENT, "gait --weights 1e999,1,1", "finite"),
    C("gait-weights-four", ARGUMENT, "gait --weights 1,2,3,4", "expected 3 weights"),
    C("gait-starts-zero", ARGUMENT, "gait --starts 0", "must be >= 1"),
    C("table1-seed-negative", ARGUMENT, "table1 --seed -1", "must be >= 0"),
    C("solver-timing-repeats-zero", ARGUMENT, "solver-timing --repeats 0", "must be >= 1"),
    C("run-time-limit-nan", ARGUMENT, "run --time-limit nan", "must be a positive number"),
    C("run-workers-zero", ARGUMENT, "run --workers 0", "must be >= 1"),
    C("replay-steps-zero", ARGUMENT, "replay {demo} --steps 0", "must be >= 1"),
    C("compare-level-one", ARGUMENT, "compare {res:valid} {res:valid} --level 1", "must be a number between 0 and 1"),
    C("export-no-format", ARGUMENT, "export {demo}", "the following arguments are required: --format"),
    C("export-unknown-format", ARGUMENT, "export {demo} --format csv", "invalid choice: 'csv'"),
    C("export-rate-zero", ARGUMENT, "export {demo} --format sto --rate 0", "must be a positive number"),
    C("export-rate-huge", ARGUMENT, "export {demo} --format qpos --rate 1e9",
      "must be at most 10000 samples per second"),
    C("export-leg-length-negative", ARGUMENT, "export {demo} --format sto --leg-length -1",
      "must be a positive number"),
    C("export-degrees-for-qpos", ARGUMENT, "export {demo} --format qpos --degrees",
      "--degrees does not apply to --format qpos"),
    C("export-rate-for-minari", ARGUMENT, "export {demo} --format minari --rate 50",
      "--rate does not apply to --format minari"),
    # --config: not JSON, too deep, unknown fields, values of the wrong type or range
    C("ioc-config-negative", CONFIG, 'ioc --config {"n_random":-1}', "n_random must be >= 0"),
    C("ioc-config-choice", CONFIG, 'ioc --config {"forward_start":"nope"}', "forward_start must be 'warm' or 'cold'"),
    C("run-config-unknown-field", CONFIG, 'run --config {"nope":1}', "unknown field(s) nope"),
    C("ioc-config-unknown-field", CONFIG, 'ioc --config {"nope":1}', "unknown field(s) nope"),
    C("ioc-config-float-for-int", CONFIG, 'ioc --config {"n_random":1.5}', "n_random must be an integer"),
    C("ioc-config-number-for-text", CONFIG, 'ioc --config {"forward_start":3}', "must be a string"),
    C(
        "ioc-config-bad-list",
        CONFIG,
        'ioc --algorithm analytic-center --config {"proximal":[1,"x"]}',
        "must be a list of finite numbers",
    ),
    C("ioc-config-nan", CONFIG, 'ioc --config {"perturbation":NaN}', "must be a finite number"),
    C("ioc-config-not-object", CONFIG, "ioc --config [1,2]", "must be a JSON object"),
    C("run-config-bool-for-int", CONFIG, 'run --config {"n_random":true}', "n_random must be an integer"),
    C("run-other-config-not-done", CONFIG, "run --out {res:other-config}",
      "holds the case log-barrier/nominal__ideal__seed0__cfg"),
    C("ioc-config-nested", CONFIG, "ioc --config {nested-json}", "JSON nested deeper than 64 levels"),
    C("run-config-nested", CONFIG, "run --config {nested-json}", "JSON nested deeper than 64 levels"),
    C("ioc-config-huge-text", CONFIG, "ioc --config {huge-config}", "n_random must be an integer, got [1, 1,"),
    C("ioc-config-huge-int", CONFIG, 'ioc --config {"n_random":100000000000000000000000}',
      "n_random must be an integer within ±2147483647"),
    C("ioc-config-1e23", CONFIG, 'ioc --config {"n_random":1e23}', "n_random must be an integer"),
    C("ioc-config-int-beyond-float", CONFIG, "ioc --config {huge-int-config}", "perturbation must be a finite number"),
    # names: commands, algorithms, suites
    C("ioc-algorithm-path", NAME, "ioc --algorithm ../x", "unknown algorithm '../x'"),
    C("run-algorithm-path", NAME, "run --algorithm ../x", "invalid algorithm name '../x'"),
    C("old-bench-command", NAME, "bench", "invalid choice: 'bench'"),
    C("run-suite-unknown", NAME, "run --suite nope", "unknown suite 'nope'"),
    C("figures-unknown-algorithm", NAME, "figures {res:valid} --algorithm nope", "not in the results"),
    C("no-such-command", NAME, "no-such-command", "invalid choice"),
    C("run-list-unknown-suite", NAME, "run --list --suite nope --json", "unknown suite 'nope'"),
    # output paths: folders and files that cannot be written, or would fail after the work
    C("ioc-out-under-file", OUTPUT, "ioc --out {file}/r.json", "/file/r.json: /"),
    C("gait-out-under-file", OUTPUT, "gait --out {file}/demo.npz", "is not a directory"),
    C("replay-out-under-file", OUTPUT, "replay {demo} --out {file}/sub", "is not a directory"),
    C("run-out-under-file", OUTPUT, "run --out {file}/results", "is not a directory"),
    C("leaderboard-out-under-file", OUTPUT, "leaderboard {res:valid} --out {file}/board", "is not a directory"),
    C("figures-out-under-file", OUTPUT, "figures {res:valid} --out {file}/figs", "is not a directory"),
    C("ioc-out-directory", OUTPUT, "ioc --out {tmp}", "is a directory"),
    C("ioc-out-png", OUTPUT, "ioc --out {tmp}/r.png", "names the JSON result"),
    C("gait-out-directory", OUTPUT, "gait --out {tmp}/dir.npz --weights 1,1,1", "is a directory"),
    C("figures-out-file", OUTPUT, "figures {res:valid} --out {file}", "exists and is not a directory"),
    C("leaderboard-out-empty", OUTPUT, "leaderboard {res:valid} --out {empty}", "empty string"),
    C("leaderboard-readme-a-folder", OUTPUT, "leaderboard {res:valid} --out {readme-dir}",
      "README.md is a directory"),
    C("gait-out-empty", OUTPUT, "gait --out {empty}", "empty string"),
    C("ioc-out-empty", OUTPUT, "ioc --out {empty}", "empty string"),
    C("run-out-empty", OUTPUT, "run --out {empty}", "empty string"),
    C("replay-out-empty", OUTPUT, "replay {demo} --out {empty}", "empty string"),
    C("figures-out-empty", OUTPUT, "figures {res:valid} --out {empty}", "empty string"),
    C("gait-out-proc", OUTPUT, "gait --out /proc/demo.npz", "under /proc"),
    C("ioc-out-sys", OUTPUT, "ioc --out /sys/ioc_result.json", "under /sys"),
    C("run-out-proc", OUTPUT, "run --out /proc/results", "under /proc"),
    C("replay-out-sys", OUTPUT, "replay {demo} --out /sys/replays", "under /sys"),
    C("leaderboard-out-proc", OUTPUT, "leaderboard {res:valid} --out /proc/board", "under /proc"),
    C("figures-out-dev", OUTPUT, "figures {res:valid} --out /dev/figs", "under /dev"),
    C("gait-out-loop", OUTPUT, "gait --out {loop}/demo.npz", "symbolic link loop"),
    C("ioc-out-loop", OUTPUT, "ioc --out {loop}", "symbolic link loop"),
    C("run-out-loop", OUTPUT, "run --out {loop}/results", "symbolic link loop"),
    C("leaderboard-out-loop", OUTPUT, "leaderboard {res:valid} --out {loop}", "symbolic link loop"),
    C("figures-out-dangling", OUTPUT, "figures {res:valid} --out {dangling}", "a symbolic link to nothing"),
    C("gait-out-long-name", OUTPUT, "gait --out {tmp}/{long}.npz", "over the 255 a file name may have"),
    C("ioc-out-long-name", OUTPUT, "ioc --out {tmp}/{long}.json", "over the 255 a file name may have"),
    C("run-out-long-name", OUTPUT, "run --out {tmp}/{long}", "over the 255 a file name may have"),
    C("replay-out-long-name", OUTPUT, "replay {demo} --out {tmp}/{long}", "over the 255 a file name may have"),
    C("replay-output-name-too-long", OUTPUT, "replay {demo:long-stem}", "over the 255 a file name may have"),
    C("leaderboard-out-long-path", OUTPUT, "leaderboard {res:valid} --out {deep}", "over the 4095 a path may have"),
    C("gait-out-fifo", OUTPUT, "gait --out {fifo}.npz", "is a FIFO, not a regular file"),
    C("ioc-out-device", OUTPUT, "ioc --out /dev/null", "under /dev"),
    C("export-sto-out-under-file", OUTPUT, "export {demo} --format sto --out {file}/x.sto", "is not a directory"),
    C("export-sto-out-directory", OUTPUT, "export {demo} --format sto --out {tmp}/dir.npz",
      "is a directory, not a file name"),
    C("export-qpos-out-proc", OUTPUT, "export {demo} --format qpos --out /proc/x.npz", "under /proc"),
    C("export-sto-out-loop", OUTPUT, "export {demo} --format sto --out {loop}/x.sto", "symbolic link loop"),
    C("export-qpos-output-name-too-long", OUTPUT, "export {demo:long-stem} --format qpos",
      "over the 255 a file name may have"),
    C("export-minari-out-a-file", OUTPUT, "export {demo} --format minari --out {file}",
      "exists and is not a directory"),
    C("export-out-is-the-demonstration", OUTPUT, "export {demo} --format qpos --out {demo}",
      "is the demonstration itself: the export would replace it"),
    # demonstration files: not a file, not an .npz, spoilt content
    C("replay-meta-list", DEMO, "replay {demo:meta-list}", "'meta' header must be a JSON object"),
    C("replay-weights-list", DEMO, "replay {demo:weights-list}", "weights must be a JSON object"),
    C("replay-q-0d", DEMO, "replay {demo:q-0d}", "array q has shape ()"),
    C("replay-tau-0d", DEMO, "replay {demo:tau-0d}", "array tau has shape ()"),
    C("replay-corrupted-member", DEMO, "replay {demo:corrupted}", "not a readable .npz"),
    C("replay-renamed-npy", DEMO, "replay {demo:renamed-npy}", "not a zip archive"),
    C("replay-nan-weights", DEMO, "replay {demo:nan-weights}", "weights['hip'] must be a finite number"),
    C("replay-nan-features", DEMO, "replay {demo:nan-features}", "features['knee'] must be a finite number"),
    C("replay-truncated", DEMO, "replay {demo:truncated}", "not a zip archive"),
    C("replay-not-npy-member", DEMO, "replay {demo:not-npy-member}", "not a readable .npz"),
    C("replay-pickled-member", DEMO, "replay {demo:pickled}", "not a readable .npz"),
    C("replay-meta-not-json", DEMO, "replay {demo:meta-not-json}", "'meta' header is not JSON"),
    C("replay-schema-99", DEMO, "replay {demo:schema-99}", "schema version 99"),
    C("replay-solver-list", DEMO, "replay {demo:solver-list}", "solver must be a JSON object"),
    C("replay-directory", DEMO, "replay {tmp}", "is a directory, not a demonstration file"),
    C("replay-missing", DEMO, "replay {tmp}/nope.npz", "demonstration file not found"),
    C("replay-dev-zero", DEMO, "replay /dev/zero", "under /dev"),
    C("replay-fifo", DEMO, "replay {demo:fifo}", "is a FIFO"),
    C("replay-passwd", DEMO, "replay /etc/passwd", "not a zip archive"),
    C("replay-meta-nested", DEMO, "replay {demo:meta-nested}", "'meta' header is JSON nested deeper than 64 levels"),
    C("replay-n-intervals-huge", DEMO, "replay {demo:n-intervals-huge}", "n_intervals must be an integer from 0"),
    C("export-missing", DEMO, "export {tmp}/nope.npz --format sto", "demonstration file not found"),
    C("export-not-a-demonstration", DEMO, "export {file} --format qpos", "not a zip archive"),
    C("export-meta-list", DEMO, "export {demo:meta-list} --format minari --out {tmp}/datasets",
      "'meta' header must be a JSON object"),
    C("export-folder-without-demonstrations", DEMO, "export {tmp}/dir.npz --format sto",
      "holds no demonstration files (*.npz)"),
    C("export-folder-with-a-folder-npz", DEMO, "export {tmp} --format sto", "is a directory, not a demonstration file"),
    # result files: not a file, not JSON, not the case their name says, values out of range
    C("leaderboard-null-result", RESULT, "leaderboard {res:null}", "expected a JSON object, got null"),
    C("figures-null-result", RESULT, "figures {res:null} --out {tmp}/figs", "expected a JSON object, got null"),
    C("run-resume-null-result", RESULT, "run --out {res:null}", "expected a JSON object, got null"),
    C("leaderboard-wall-time-text", RESULT, "leaderboard {res:wall-time}", 'wall_time must be a number, got "fast"'),
    C("figures-wall-time-text", RESULT, "figures {res:wall-time} --out {tmp}/figs", "wall_time must be a number"),
    C("run-unreadable-result", RESULT, "run --out {res:not-json}", "not JSON"),
    C("run-results-in-use", RESULT, "run --out {res:valid}", "another run is writing", hold="{res:valid}"),
    C("leaderboard-list-result", RESULT, "leaderboard {res:list}", "expected a JSON object, got list"),
    C("leaderboard-short-weights", RESULT, "leaderboard {res:weights-2}", "weights has 2 entries for 3 features"),
    C("leaderboard-unknown-field", RESULT, "leaderboard {res:unknown-field}", "unknown field(s) surprise"),
    C("leaderboard-empty-dir", RESULT, "leaderboard {res:empty}", "no case results"),
    C("leaderboard-missing-dir", RESULT, "leaderboard {res:missing}", "results directory not found"),
    C("figures-escaping-algorithm", RESULT, "figures {res:escaping-algorithm} --out {tmp}/figs",
      "invalid algorithm name 'x/../../ESCAPED'"),
    C("run-linked-algorithm-folder", RESULT, "run --out {res:linked-folder}", "leads out of"),
    C("leaderboard-result-link-passwd", RESULT, "leaderboard {res:link-passwd}", "is a symbolic link"),
    C("leaderboard-result-link-zero", RESULT, "leaderboard {res:link-zero}", "is a symbolic link"),
    C("leaderboard-result-fifo", RESULT, "leaderboard {res:fifo}", "is a FIFO, not a regular file"),
    C("figures-result-directory", RESULT, "figures {res:directory} --out {tmp}/figs", "is a directory"),
    C("run-result-fifo", RESULT, "run --out {res:fifo}", "is a FIFO"),
    C("leaderboard-other-algorithm", RESULT, "leaderboard {res:other-algorithm}",
      "holds the case analytic-center/nominal__ideal__seed0, not the one its name says"),
    C("run-other-algorithm-not-done", RESULT, "run --out {res:other-algorithm}", "holds the case analytic-center/"),
    C("leaderboard-other-seed", RESULT, "leaderboard {res:other-seed}",
      "holds the case log-barrier/nominal__ideal__seed1"),
    C("leaderboard-case-key-other", RESULT, "leaderboard {res:case-key-other}", "records case_key"),
    C("leaderboard-unknown-condition", RESULT, "leaderboard {res:unknown-condition}", "unknown condition 'nope'"),
    C("leaderboard-unknown-weight-set", RESULT, "leaderboard {res:unknown-weight-set}", "unknown weight set 'nope'"),
    C("leaderboard-duplicate-features", RESULT, "leaderboard {res:duplicate-features}", "distinct known features"),
    C("figures-unknown-feature", RESULT, "figures {res:unknown-feature} --out {tmp}/figs", "distinct known features"),
    C("leaderboard-negative-error", RESULT, "leaderboard {res:negative-error}",
      "weight_error must be a number from 0 to 1"),
    C("leaderboard-negative-time", RESULT, "leaderboard {res:negative-time}", "wall_time must be a number from 0 to"),
    C("leaderboard-zero-truth", RESULT, "leaderboard {res:zero-truth}", "true_weights [0.0, 0.0, 0.0] are not"),
    C("leaderboard-wrong-truth", RESULT, "leaderboard {res:wrong-truth}", "are not the truth of weight set 'nominal'"),
    C("leaderboard-huge-n-solves", RESULT, "leaderboard {res:huge-n-solves}", "n_solves must be between 0 and"),
    C("leaderboard-multiline-status", RESULT, "leaderboard {res:multiline-status}", "status must be one line of 1 to"),
    C("leaderboard-nested-result", RESULT, "leaderboard {res:nested}", "JSON nested deeper than 64 levels"),
    C("compare-missing-dir", RESULT, "compare {res:missing} {res:valid}", "results directory not found"),
    C("compare-empty-dir", RESULT, "compare {res:valid} {res:empty}", "no case results"),
    C("compare-a-file", RESULT, "compare {res:valid} {file}", "is a file: compare reads two results folders"),
    C("compare-no-case-in-common", RESULT, "compare {res:valid} {res:other-case}", "have no case in common"),
    C("compare-unreadable-result", RESULT, "compare {res:valid} {res:not-json}", "not JSON"),
    C("compare-null-result", RESULT, "compare {res:null} {res:valid}", "expected a JSON object, got null"),
    # the demonstration cache
    C("ioc-cache-a-file", CACHE, "ioc", "/file/demos: /", cache="{file}"),
    C("run-cache-a-file", CACHE, "run --out {tmp}/results", "demonstration cache", cache="{file}"),
    C("run-cache-empty", CACHE, "run --out {tmp}/results", "IOC_BENCH_CACHE is set but empty", cache="{empty}"),
    C("ioc-cache-proc", CACHE, "ioc --out {tmp}/r.json", "under /proc", cache="/proc/cache"),
    # the Ray cluster
    C("run-address-without-ray", CLUSTER, "run --address 127.0.0.1:6379", "--address is for the ray executor"),
    C("run-ray-unreachable", CLUSTER, "run --executor ray --address 127.0.0.1:9", "cannot reach a Ray cluster"),
    C("run-ray-bad-address", CLUSTER, "run --executor ray --address nowhere:99999", "cannot reach a Ray cluster"),
    C("replay-missing-array", CLUSTER, "replay {demo:missing-q}", "missing trajectory arrays ['q']"),
]  # fmt: skip


@pytest.fixture(scope="module")
def good_demo(nominal_demo, tmp_path_factory) -> Path:
    return nominal_demo.save(tmp_path_factory.mktemp("good") / "good.npz")


#: Length of every scratch folder's path here: messages shorten deep paths and cut long lines at
#: fixed lengths, so the table reads the same whatever the length of pytest's temporary folder.
SCRATCH_PATH_CHARS = 240
#: What pads a scratch folder's path to that length (no letter the table's placeholders use).
PAD = "w"


@pytest.fixture
def scratch() -> Path:
    """A new folder whose path has :data:`SCRATCH_PATH_CHARS` characters, made under ``/tmp``
    when it is writable (else the system's temporary folder), never under pytest's, whose
    depth is the user's ``--basetemp``; removed afterwards."""
    base = "/tmp" if os.access("/tmp", os.W_OK) else tempfile.gettempdir()
    root = Path(tempfile.mkdtemp(prefix="iocb-", dir=base))
    room = SCRATCH_PATH_CHARS - len(str(root)) - 1
    assert room >= 100, f"the temporary folder {root} is too deep for this test's fixed-length scratch"
    folder = root / (PAD * room)
    folder.mkdir()
    yield folder
    shutil.rmtree(root, ignore_errors=True)


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
def test_bad_input_exits_2_with_one_line(case: Case, scratch, good_demo, make_result, capsys, no_work, monkeypatch):
    space = Workspace(scratch, good_demo, make_result)
    argv = [space.resolve(a) for a in case.argv]
    hold = space.resolve(case.hold) if case.hold else None
    if case.cache:
        monkeypatch.setenv("IOC_BENCH_CACHE", space.resolve(case.cache))
    cwd = scratch.parent / "cwd"
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
    """``leaderboard R --out R/board`` twice: the second run does not read the first one's
    leaderboard.json as a result file."""
    root = make_results(tmp_path, "valid", make_result)
    for _ in range(2):
        assert main(["leaderboard", str(root), "--out", str(root / "board"), "--json"]) == 0
        cells = json.loads(capsys.readouterr().out)["cells"]
        assert sum(c["cases"] for c in cells) == 1
    ROWS["leaderboard-out-inside-results"] = (
        OUTPUT,
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
    # arguments: numbers and options out of range
    ('optimize_gait(task=0.27)', ARGUMENT, lambda t, g: optimize_gait(task=0.27),
     ValueError, "task must be a Task (e.g. Task(speed=0.27)), got float 0.27"),
    ('optimize_gait(init="x.npz")', ARGUMENT, lambda t, g: optimize_gait(init="x.npz"),
     ValueError, "init must be a Demonstration"),
    ("Task(True)", ARGUMENT, lambda t, g: Task(True), ValueError, "speed must be a positive finite number, got True"),
    ("optimize_gait(workers=0)", ARGUMENT, lambda t, g: optimize_gait(workers=0),
     ValueError, "workers must be an integer >= 1 or None, got 0"),
    ('optimize_gait("1,2")', ARGUMENT, lambda t, g: optimize_gait("1,2"),
     ValueError, "expected 3 weights (hip, knee, dtau) or 6"),
    ("run_case(seed=-1)", ARGUMENT, lambda t, g: run_case(seed=-1), ValueError, "seed must be a non-negative integer"),
    ("optimize_gait(seed=-1)", ARGUMENT, lambda t, g: optimize_gait(seed=-1), ValueError, "non-negative integer"),
    ('parse_weights({"hip": None})', ARGUMENT, lambda t, g: ioc_bench.parse_weights({"hip": None}),
     ValueError, "weights must be numbers"),
    ("Task(10**400)", ARGUMENT, lambda t, g: Task(10**400),
     ValueError, "speed must be a positive finite number, got an integer of about 401 digits"),
    ("Task(0.27, step_length=np.inf)", ARGUMENT, lambda t, g: Task(0.27, step_length=np.inf),
     ValueError, "step_length must be a positive finite number"),
    ('run_case(weights="penalize-knee", demo=<a nominal demonstration>)', ARGUMENT,
     lambda t, g: run_case(weights="penalize-knee", demo=Demonstration.load(g)),
     ValueError, "demo was made with weights"),
    ('optimize_gait(params="walker")', ARGUMENT, lambda t, g: optimize_gait(params="walker"),
     ValueError, "params must be a WalkerParams (e.g. WalkerParams()), got str 'walker'"),
    ('optimize_gait(model="walker")', ARGUMENT, lambda t, g: optimize_gait(model="walker"),
     ValueError, "model must be a GaitModel"),
    ('optimize_gait(rules="paper")', ARGUMENT, lambda t, g: optimize_gait(rules="paper"),
     ValueError, "rules must be a StepRules"),
    ('optimize_gait(guesses="demo.npz")', ARGUMENT, lambda t, g: optimize_gait(guesses="demo.npz"),
     ValueError, "guesses must be a list of Demonstrations"),
    ('optimize_gait(guesses=["demo.npz"])', ARGUMENT, lambda t, g: optimize_gait(guesses=["demo.npz"]),
     ValueError, "each of guesses must be a Demonstration"),
    ("optimize_gait(starts=10**9)", ARGUMENT, lambda t, g: optimize_gait(starts=10**9),
     ValueError, "starts must be at most 10000"),
    # --config: not JSON, too deep, unknown fields, values of the wrong type or range
    ("run_case(config=[1, 2])", CONFIG, lambda t, g: run_case(config=[1, 2]),
     ValueError, "an algorithm config must be a mapping"),
    ('run_case(config={"n_random": "3"})', CONFIG, lambda t, g: run_case(config={"n_random": "3"}),
     ValueError, "n_random must be an integer"),
    # names: commands, algorithms, suites
    ('run_cases(executor="nope")', NAME, lambda t, g: _run_cases_unknown_executor(t),
     ValueError, "unknown executor 'nope'; valid: local, ray"),
    ('CaseSpec("../x", ...)', NAME, lambda t, g: CaseSpec("../x", "nominal", "ideal", 0),
     ValueError, "invalid algorithm name"),
    # output paths: folders and files that cannot be written, or would fail after the work
    ('Demonstration.save("/proc/demo.npz")', OUTPUT, lambda t, g: Demonstration.load(g).save("/proc/demo.npz"),
     PathError, "under /proc"),
    ('run_cases(out="")', OUTPUT, lambda t, g: _run_cases_into(""), PathError, "empty string"),
    ('run_cases(out="/proc/results")', OUTPUT, lambda t, g: _run_cases_into("/proc/results"),
     PathError, "under /proc"),
    ('make_figures(out_dir="")', OUTPUT, lambda t, g: make_figures(_results(t, "valid"), ""),
     PathError, "empty string"),
    ("write_leaderboard (README.md a folder)", OUTPUT, lambda t, g: _board_into_readme_folder(t),
     PathError, "README.md is a directory"),
    ('check_output_dir("/sys/x")', OUTPUT, lambda t, g: check_output_dir("/sys/x"), PathError, "under /sys"),
    # demonstration files: not a file, not an .npz, spoilt content
    ("Demonstration.load (meta a list)", DEMO, lambda t, g: Demonstration.load(make_demo(t, g, "meta-list")),
     DemonstrationFileError, "'meta' header must be a JSON object"),
    ("Demonstration.load (weights a list)", DEMO, lambda t, g: Demonstration.load(make_demo(t, g, "weights-list")),
     DemonstrationFileError, "weights must be a JSON object"),
    ("Demonstration.load (0-d q)", DEMO, lambda t, g: Demonstration.load(make_demo(t, g, "q-0d")),
     DemonstrationFileError, "array q has shape ()"),
    ("Demonstration.load (corrupted member)", DEMO, lambda t, g: Demonstration.load(make_demo(t, g, "corrupted")),
     DemonstrationFileError, "not a readable .npz"),
    ("Demonstration.load (renamed .npy)", DEMO, lambda t, g: Demonstration.load(make_demo(t, g, "renamed-npy")),
     DemonstrationFileError, "not a zip archive"),
    ("Demonstration.load(None)", DEMO, lambda t, g: Demonstration.load(None),
     DemonstrationFileError, "path must be a demonstration file's path (str or os.PathLike), got NoneType"),
    ("Demonstration.load(5)", DEMO, lambda t, g: Demonstration.load(5), DemonstrationFileError, "got int"),
    ('Demonstration.load("")', DEMO, lambda t, g: Demonstration.load(""), DemonstrationFileError, "empty string"),
    ('Demonstration.load("/dev/zero")', DEMO, lambda t, g: Demonstration.load("/dev/zero"),
     DemonstrationFileError, "under /dev"),
    ("Demonstration.load (a FIFO)", DEMO, lambda t, g: Demonstration.load(_fifo(t, "demo.npz")),
     DemonstrationFileError, "is a FIFO, not a regular file"),
    ("Demonstration.load (meta nested 100000 deep)", DEMO,
     lambda t, g: Demonstration.load(make_demo(t, g, "meta-nested")),
     DemonstrationFileError, "'meta' header is JSON nested deeper than 64 levels"),
    # result files: not a file, not JSON, not the case their name says, values out of range
    ("read_result (a FIFO)", RESULT, lambda t, g: read_result(_fifo(t, "nominal__ideal__seed0.json")),
     ResultFileError, "is a FIFO, not a regular file"),
    ("load_results (another algorithm's result under log-barrier/)", RESULT,
     lambda t, g: load_results(_results(t, "other-algorithm")),
     ResultFileError, "holds the case analytic-center/nominal__ideal__seed0"),
    ("parse_result (n_solves 10**30)", RESULT,
     lambda t, g: parse_result(_SYNTHETIC[0]().to_dict() | {"n_solves": 10**30}),
     ValueError, "n_solves must be between 0 and 1000000000"),
    ("write_result (algorithm folder a link out)", RESULT,
     lambda t, g: write_result(_results(t, "linked-folder"), CaseSpec("log-barrier", "nominal", "ideal", 0),
                               _SYNTHETIC[0]()),
     ResultFileError, "leads out of"),
    ("make_figures (algorithm x/../../ESCAPED)", RESULT,
     lambda t, g: make_figures(_results(t, "escaping-algorithm"), t / "figs"),
     ResultFileError, "invalid algorithm name 'x/../../ESCAPED'"),
    # input files
    ('read_bytes("/dev/zero", 10)', INPUT, lambda t, g: read_bytes("/dev/zero", 10), PathError, "under /dev"),
]  # fmt: skip


@pytest.mark.parametrize(("name", "source", "call", "error", "expect"), API_CASES, ids=[c[0] for c in API_CASES])
def test_python_api_raises_one_documented_error(
    name, source, call, error, expect, scratch, good_demo, no_work, make_result
):
    _SYNTHETIC[:] = [make_result]
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
        # and its end holds the scratch's padding (after the end of pytest's folder, if that is kept too)
        text = re.sub(rf"<tmp>\.\.\.(?:[^/\s]*/)?{PAD}+(?=/)", "<tmp>", text)
        text = text.replace(str(tmp), "<tmp>")
        text = re.sub(r"/\S*?pytest-\d+/[^/'\s.]*", "<tmp>", text)  # a scratch path cut short in a message
    return text.replace("|", "\\|")


#: How results are handled: what could go wrong, what holds instead, and where that is shown.
RESULT_HANDLING = [
    ("results of several configs pooled into one leaderboard cell", "cells are (algorithm, config)",
     "tests/bench/test_leaderboard.py::test_configs_never_share_a_cell_and_the_header_names_each"),
    ("a config that only spells out defaults makes a second case", "configs are canonical before hashing",
     "tests/bench/test_results.py::test_a_config_spelling_out_defaults_is_the_same_case"),
    ("timeouts, dead workers and config errors count as done forever",
     "failed cases are retried by default (--keep-failed keeps them); config errors are refused before work",
     "tests/bench/test_runner.py::test_timeouts_and_dead_workers_are_recorded_then_retried, "
     "::test_smoke_suite_killed_midway_resumes_and_retries_a_failed_case"),
    ("an executor overwrites a success just written with a failure",
     "one scheduler calls finish once per case; an error while recording stops the run",
     "tests/bench/test_runner.py::test_an_error_while_recording_a_success_stops_the_run_and_is_never_recorded_as_a_failure"),
    ("an algorithm name like ../x writes outside the results folder", "names are checked as folder names",
     "tests/ioc/test_registry.py::test_names_that_cannot_be_folder_names_are_refused, "
     "tests/bench/test_results.py::test_a_bad_case_is_refused_when_made"),
    ("a leaderboard half written (README.md without leaderboard.json)", "both rendered, then written together",
     "tests/bench/test_leaderboard.py::test_the_two_files_are_written_together_or_not_at_all"),
    ("a writer killed mid-write leaves a tmp file", "unnamed (O_TMPFILE) staging; leftovers removed by the next run",
     "tests/test_fileio.py::test_sigkill_at_every_line_of_a_write_leaves_old_or_new_never_half"),
]  # fmt: skip


#: Hostile inputs, by class: what they could do, what holds instead, and where that is shown
#: (besides the rows above).
HOSTILE_HANDLING = [
    ("a result whose algorithm is x/../../ESCAPED makes figures write a PNG outside --out",
     "a result's algorithm must be a valid name; figure file names are built from checked names only",
     "tests/viz/test_figures.py::test_output_names_come_from_checked_identifiers_only"),
    ("run follows a linked algorithm folder inside --out and writes outside it",
     "every case's folder must resolve inside --out: checked for every case before the run, again before each write",
     "tests/bench/test_results.py::test_a_case_folder_leading_out_of_the_results_is_refused_before_and_at_writing"),
    ("readers follow links named like results (/etc/passwd, /dev/zero), a FIFO blocks leaderboard forever",
     "result files are opened without following links and without blocking, checked to be regular files on the "
     "open descriptor, at most 32 MiB read",
     "tests/test_paths.py::test_read_bytes_opens_regular_files_only_within_a_limit, "
     "tests/test_hostile_inputs.py::test_property_a_hostile_input_path_is_refused_without_blocking"),
    ("leaderboard --out '' writes into the current folder; replay leaves MUJOCO_LOG.TXT there",
     "every path argument is parsed by one type that refuses ''; MuJoCo warnings go to stderr",
     "tests/cli/test_replay_cli.py::test_mujoco_warnings_go_to_stderr_not_to_a_log_file"),
    ("one algorithm's results filed under another's names are taken as done, and mixed in the leaderboard; "
     "a case in several files is counted several times",
     "a file's content must be the case its name says (every CaseSpec field compared through the key), so one "
     "case has one file; run refuses a file that is not its own case",
     "tests/bench/test_results.py::test_stored_result_is_never_another_case, "
     "tests/test_hostile_inputs.py::test_property_a_record_under_another_case_name_is_refused"),
    ("another algorithm, unknown condition or weight set, duplicate or unknown features, negative errors or times, "
     "zero true weights are rendered as valid; n_solves 10**30 ends in a traceback",
     "every field typed and in range, the true weights the weight set's",
     "tests/bench/test_results.py::test_out_of_range_values_are_refused, "
     "tests/test_hostile_inputs.py::test_property_a_spoilt_record_is_refused_with_one_line_naming_the_file"),
    ("run_case(demo=<penalize-knee demonstration>, weights='nominal') scores against the wrong truth",
     "refused by the one case pipeline (synthetic/case.py): a demonstration of another case is a ValueError",
     "the API row run_case(weights=\"penalize-knee\", demo=...) above"),
    ("outputs under /proc or /sys, through a link loop, with a 256-byte name, or '' pass a check "
     "(os.access says yes as root) and fail after the solve",
     "one policy (ioc_bench.paths) for every command and the API, writability probed by making an unnamed file",
     "tests/test_paths.py::test_output_dirs_that_would_fail_after_the_work_are_refused, "
     "tests/test_hostile_inputs.py::test_property_every_command_refuses_a_hostile_path_before_any_work"),
    ("IOC_BENCH_CACHE naming a file fails after the work", "the cache folder is checked before the work (ioc, run)",
     "rows ioc-cache-a-file, run-cache-a-file above"),
    ("README.md being a folder in the leaderboard's --out leaves a temporary file",
     "refused up front; atomic_write_many removes every staged temporary when a rename fails",
     "tests/test_fileio.py::test_atomic_write_many_leaves_no_temporary_when_a_rename_fails"),
    ("deep JSON raises RecursionError; a 100 KB config is echoed whole; n_random 1e23 is accepted",
     "JSON from outside is read at most 64 levels deep; messages are cut to 400 characters; ints are ints, "
     "config ints within a C int",
     "tests/test_hostile_inputs.py::test_property_json_of_any_depth_is_a_value_or_a_value_error"),
    ("run --list --suite nope --json ignores both; an unknown algorithm lists refused plugins; a plugin named "
     "like a built-in is ignored silently",
     "--list honours both; only algorithms that load are listed; the clash is reported as 'name clash refused'",
     "tests/cli/test_plugins_cli.py"),
    ("Task(10**400) raises OverflowError; Task(np.float32(0.27)) is refused",
     "every positive finite real is a speed (NumPy scalars at their own precision's decimal), the rest a ValueError",
     "tests/test_hostile_inputs.py::test_property_task_takes_every_positive_finite_real"),
    ("the differentiable view, IOCProblem.optimize(starts=10**9), gym.make(..., demonstration=5), "
     "reset(options=5), NaN reward settings",
     "not in this table: the IOC problem's (ioc/) and the environment's (envs/) own checks", "-"),
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
    ("paths.check_* / read_bytes / check_inside / check_file_name", "PathError", ""),
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
        "What a path may be is decided in one place, `ioc_bench.paths`, for every command and the API: not empty,",
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
        "| # | input | command | exit | message (stderr, one line) |",
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
        "| # | input | call | raises | message |",
        "|---|---|---|---|---|",
    ]
    for i, (name, *_rest) in enumerate(API_CASES, 1):
        source, error, message = API_ROWS[name]
        lines.append(f"| {i} | {source} | `{name}` | {error} | {message} |")
    lines += ["", "## Result handling", "", "| what could go wrong | what holds | shown by |", "|---|---|---|"]
    lines += [f"| {risk} | {holds} | `{test}` |" for risk, holds, test in RESULT_HANDLING]
    lines += ["", "## Hostile inputs, by class", "", "| what they could do | what holds | shown by |", "|---|---|---|"]
    lines += [f"| {risk} | {holds} | {_code(test)} |" for risk, holds, test in HOSTILE_HANDLING]
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
