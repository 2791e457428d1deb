"""Bad input, swept: a broad sample of hostile inputs per class of input, counted.

    python studies/bad_input_sweep.py            # ~1 min; prints a table per class and every miss
    python studies/bad_input_sweep.py --verbose  # also every input with its message

Every command line runs in-process with solving replaced by a trap, from an empty current
folder, under a 10 s alarm. A command line counts as *handled* when it exits with code 2 and
exactly one stderr line (no traceback, at most 450 characters), before any expensive work,
within the alarm, leaving its scratch folder and the current folder as they were (nothing
written outside --out, no temporary left). A Python call is handled when it raises a
``ValueError`` (the documented error types all are) with a one-line message, in time, and
changes nothing on disk. The inputs are generated here, most of them beyond the ones
``tests/cli/test_bad_input.py`` lists.
"""

from __future__ import annotations

import argparse
import contextlib
import io
import json
import os
import signal
import stat
import sys
import tempfile
import time
from collections import defaultdict
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import numpy as np

TIME_LIMIT = 10


class _Trap(Exception):
    """Raised where expensive work would start."""


class _Alarm(Exception):
    """Raised when an input takes longer than :data:`TIME_LIMIT` (a hang)."""


@dataclass
class Outcome:
    klass: str
    label: str
    handled: bool
    why: str
    message: str


# -- the scratch world --------------------------------------------------------------------------


class World:
    """A scratch folder with one good demonstration and one good results folder to spoil."""

    def __init__(self, root: Path, demo_bytes: bytes, record: dict):
        self.root, self.demo_bytes, self.record = root, demo_bytes, record
        self.n = 0

    def fresh(self) -> Path:
        self.n += 1
        path = self.root / f"w{self.n}"
        path.mkdir()
        return path

    def demo(self, where: Path, name: str = "demo.npz") -> Path:
        (where / name).write_bytes(self.demo_bytes)
        return where / name

    def results(self, where: Path, content: str | dict | None = None, node: str = "") -> Path:
        """``where/results`` holding ``log-barrier/nominal__ideal__seed0.json`` (spoilt as asked)."""
        root = where / "results"
        (root / "log-barrier").mkdir(parents=True)
        path = root / "log-barrier" / "nominal__ideal__seed0.json"
        if node:
            make_node(path, node, where)
        else:
            data = self.record if content is None else content
            path.write_text(data if isinstance(data, str) else json.dumps(data))
        return root


def make_node(path: Path, kind: str, where: Path) -> None:
    """Put something that is not a plain file (or a plain file in the wrong place) at ``path``."""
    if kind.startswith("link:"):
        path.symlink_to(kind[5:])
    elif kind == "fifo":
        os.mkfifo(path)
    elif kind == "dir":
        path.mkdir()
    elif kind == "loop":
        path.symlink_to(path)
    elif kind == "dangling":
        path.symlink_to(where / "nothing")
    elif kind == "socket":
        import socket

        s = socket.socket(socket.AF_UNIX)
        s.bind(str(path))
        s.close()
    else:
        raise KeyError(kind)


def hostile_path(where: Path, kind: str, suffix: str = "") -> str:
    """A path of ``kind`` (built under ``where``) that no command may accept as an output."""
    if kind == "empty":
        return ""
    if kind == "nul":
        return str(where / f"a\0b{suffix}")
    if kind.startswith("long-name-"):
        return str(where / ("n" * int(kind.rsplit("-", 1)[1]) + suffix))
    if kind == "long-path":
        return str(where / "/".join(["d" * 250] * 17)) + suffix
    if kind.startswith("under:"):
        return kind[6:] + f"/ioc-bench-out{suffix}"
    if kind == "loop":
        (where / "loop").symlink_to(where / "loop")
        return str(where / "loop" / f"x{suffix}")
    if kind == "loop2":
        (where / f"la{suffix}").symlink_to(where / f"lb{suffix}")
        (where / f"lb{suffix}").symlink_to(where / f"la{suffix}")
        return str(where / f"la{suffix}")
    if kind == "dangling":
        (where / f"dangling{suffix}").symlink_to(where / "nothing")
        return str(where / f"dangling{suffix}")
    if kind.startswith("link-to:"):
        (where / "lnk").symlink_to(kind[8:])
        return str(where / "lnk" / f"x{suffix}")
    if kind == "under-file":
        (where / "plain").write_text("x")
        return str(where / "plain" / "sub" / f"x{suffix}")
    if kind == "fifo":
        os.mkfifo(where / f"fifo{suffix}")
        return str(where / f"fifo{suffix}")
    if kind.startswith("device:"):
        return kind[7:]
    raise KeyError(kind)


PATH_KINDS = [
    "empty", "nul", "long-name-256", "long-name-1000", "long-path", "under:/proc", "under:/proc/self",
    "under:/sys", "under:/sys/kernel", "under:/dev", "loop", "loop2", "dangling", "link-to:/proc/self",
    "link-to:/sys", "under-file",
]  # fmt: skip
FILE_PATH_KINDS = [*PATH_KINDS, "fifo", "device:/dev/null", "device:/dev/zero", "device:/dev/full"]


# -- running one input ---------------------------------------------------------------------------


def snapshot(*roots: Path) -> dict[str, tuple]:
    found = {}
    for root in roots:
        for folder, dirs, names in os.walk(root):
            for name in dirs + names:
                st = os.lstat(Path(folder) / name)
                found[str(Path(folder) / name)] = (stat.S_IFMT(st.st_mode), st.st_size, st.st_mtime_ns)
    return found


@contextlib.contextmanager
def alarm(seconds: int):
    def ring(*_):
        raise _Alarm()

    old = signal.signal(signal.SIGALRM, ring)
    signal.alarm(seconds)
    try:
        yield
    finally:
        signal.alarm(0)
        signal.signal(signal.SIGALRM, old)


def run_cli(klass: str, label: str, argv: list[str], where: Path, cwd: Path, env: dict | None = None) -> Outcome:
    from ioc_bench.cli import main

    before = snapshot(where, cwd)
    err, out = io.StringIO(), io.StringIO()
    saved = {k: os.environ.get(k) for k in env or {}}
    os.environ.update(env or {})
    code, why = None, ""
    try:
        with alarm(TIME_LIMIT), contextlib.redirect_stderr(err), contextlib.redirect_stdout(out):
            try:
                code = main(argv)
            except SystemExit as exc:
                code = exc.code
    except _Trap:
        why = "expensive work started"
    except _Alarm:
        why = f"no answer within {TIME_LIMIT} s"
    except BaseException as exc:  # a traceback is a miss
        why = f"raised {type(exc).__name__}: {str(exc)[:80]}"
    finally:
        for k, v in saved.items():
            if v is None:
                os.environ.pop(k, None)
            else:
                os.environ[k] = v
    lines = err.getvalue().splitlines()
    if not why:
        if code != 2:
            why = f"exit code {code}"
        elif len(lines) != 1 or "Traceback" in err.getvalue():
            why = f"{len(lines)} stderr lines"
        elif len(lines[0]) > 450:
            why = f"a {len(lines[0])}-character line"
        elif snapshot(where, cwd) != before:
            why = "changed files"
    return Outcome(klass, label, not why, why, lines[0] if lines else "")


def run_api(klass: str, label: str, call: Callable[[], object], where: Path) -> Outcome:
    before = snapshot(where)
    why, message = "", ""
    try:
        with alarm(TIME_LIMIT):
            call()
        why = "accepted"
    except _Trap:
        why = "expensive work started"
    except _Alarm:
        why = f"no answer within {TIME_LIMIT} s"
    except ValueError as exc:
        message = str(exc)
        if "\n" in message:
            why = "a multi-line message"
    except BaseException as exc:
        why = f"raised {type(exc).__name__}: {str(exc)[:80]}"
    if not why and snapshot(where) != before:
        why = "changed files"
    return Outcome(klass, label, not why, why, message)


# -- the inputs, by class -----------------------------------------------------------------------


def out_argv(w: World, cmd: str, where: Path, out: str) -> list[str]:
    """``cmd`` with ``--out out`` (and what it reads: a good demonstration or results folder)."""
    if cmd == "replay":
        return ["replay", str(w.demo(where)), "--out", out]
    if cmd in ("leaderboard", "figures"):
        return [cmd, str(w.results(where)), "--out", out]
    return [cmd, "--out", out]


def reader_argv(cmd: str, res: Path, where: Path) -> list[str]:
    """``cmd`` reading the results folder ``res``."""
    if cmd == "figures":
        return [cmd, str(res), "--out", str(where / "f")]
    if cmd == "run":
        return ["run", "--out", str(res)]
    return [cmd, str(res)]


def security(w: World, cwd: Path) -> list[Outcome]:
    out = []
    for name in ["x/../../ESCAPED", "../../x", "/tmp/abs", "a/b", "..", ".", "", "x\ny", "x∕y", "é", "a" * 300]:
        where = w.fresh()
        res = w.results(where, w.record | {"algorithm": name})
        for cmd in (["figures", str(res), "--out", str(where / "figs")], ["leaderboard", str(res)]):
            out.append(run_cli("security", f"{cmd[0]}: algorithm {name[:20]!r}", cmd, where, cwd))
    for target in ["..", "/tmp", "/proc/self", "/", "loop"]:
        where = w.fresh()
        root = where / "results"
        root.mkdir()
        link = root / "log-barrier"
        link.symlink_to(link if target == "loop" else (where if target == ".." else target))
        out.append(run_cli("security", f"run: algorithm folder -> {target}", ["run", "--out", str(root)], where, cwd))
    nodes = ["link:/etc/passwd", "link:/dev/zero", "link:/dev/urandom", "link:/proc/self/environ", "fifo", "dir",
             "loop", "dangling", "socket", "link:/tmp"]  # fmt: skip
    for node in nodes:
        for cmd in ("leaderboard", "figures", "run"):
            where = w.fresh()
            argv = reader_argv(cmd, w.results(where, node=node), where)
            out.append(run_cli("security", f"{cmd}: result file is {node}", argv, where, cwd))
    for cmd in ("gait", "ioc", "run", "replay", "leaderboard", "figures"):
        where = w.fresh()
        out.append(run_cli("security", f"{cmd} --out ''", out_argv(w, cmd, where, ""), where, cwd))
    for thing in ("README.md", "leaderboard.json"):
        for node in ("dir", "fifo", "link:/dev/null"):
            where = w.fresh()
            res = w.results(where)
            (where / "board").mkdir()
            make_node(where / "board" / thing, node, where)
            argv = ["leaderboard", str(res), "--out", str(where / "board")]
            out.append(run_cli("security", f"leaderboard: {thing} is {node}", argv, where, cwd))
    return out


def _spoils(record: dict) -> list[tuple[str, object]]:
    big = 10**30
    return [
        ("algorithm", "analytic-center"), ("seed", 1), ("seed", -1), ("seed", 1.5), ("weight_set", "penalize-hip"),
        ("weight_set", "nope"), ("weight_set", "0,0,0"), ("weight_set", "-1,1,1"), ("condition", "noise"),
        ("condition", "nope"), ("config", {"n_random": 3}), ("features", ["hip", "hip", "dtau"]),
        ("features", ["hip", "knee", "bogus"]), ("features", ["knee", "hip", "dtau"]), ("features", []),
        ("true_weights", [0, 0, 0]), ("true_weights", [1, 0, 0]), ("true_weights", [-1, 1, 1]),
        ("weights", [0, 0, 0]), ("weights", [-1, 1, 1]), ("weights", [None, 1, 1]), ("weights", [1, 1]),
        ("weight_error", -0.1), ("weight_error", 2.0), ("weight_error", None), ("trajectory_error", -1),
        ("found_trajectory_error", -1), ("wall_time", -1), ("wall_time", None), ("wall_time", big),
        ("wall_time", "fast"), ("n_solves", -1), ("n_solves", big), ("n_solves", 1.5), ("n_solves", True),
        ("chosen_iteration", 99), ("chosen_iteration", -1), ("status", ""), ("status", "a\tb"),
        ("status", "x" * 600), ("status", "ok\nFAKE"), ("demo_speed", -1), ("demo_features", {"bogus": 1}),
        ("demo_features", {"hip": None}), ("case_key", "log-barrier/nominal__ideal__seed1"),
        ("case_key", "../x"), ("case_config", {"n_random": 3}), ("history", [1, 2]), ("surprise", 1),
        ("family", 5), ("config", [1]), ("notes", "@deep"), ("oracle", "@deep"),
    ]  # fmt: skip


def trusted_results(w: World, cwd: Path) -> list[Outcome]:
    out = []
    deep = "[" * 50_000 + "]" * 50_000
    for field, value in _spoils(w.record):
        text = json.dumps(w.record | {field: value})
        if value == "@deep":
            text = text.replace('"@deep"', deep)
        for cmd in ("leaderboard", "figures", "run"):
            where = w.fresh()
            argv = reader_argv(cmd, w.results(where, text), where)
            out.append(run_cli("result files", f"{cmd}: {field}={str(value)[:24]}", argv, where, cwd))
    for text, label in [("", "empty"), ("null", "null"), ("[]", "list"), ("{", "truncated"), ("\xff\xfe", "binary")]:
        where = w.fresh()
        out.append(run_cli("result files", f"leaderboard: {label}", ["leaderboard", str(w.results(where, text))],
                           where, cwd))  # fmt: skip
    return out


def late_paths(w: World, cwd: Path) -> list[Outcome]:
    out = []
    for kind in FILE_PATH_KINDS:
        for cmd in ("gait", "ioc", "run", "replay", "leaderboard", "figures"):
            where = w.fresh()
            suffix = {"gait": ".npz", "ioc": ".json"}.get(cmd, "")
            if cmd in ("run", "replay", "leaderboard", "figures") and kind.startswith("device:"):
                continue  # folders: a device is covered by "under:/dev"
            argv = out_argv(w, cmd, where, hostile_path(where, kind, suffix))
            out.append(run_cli("paths", f"{cmd} --out {kind}", argv, where, cwd))
    for kind in ["fifo", "device:/dev/zero", "device:/dev/urandom", "loop", "dangling", "under:/proc", "empty",
                 "long-name-300", "under-file"]:  # fmt: skip
        for cmd in ("replay", "leaderboard", "figures"):
            where = w.fresh()
            p = hostile_path(where, kind, ".npz" if cmd == "replay" else "")
            out.append(run_cli("paths", f"{cmd} reads {kind}", [cmd, p], where, cwd))
    for kind in ["empty", "under-file", "under:/proc", "under:/sys", "loop", "dangling", "fifo", "long-name-300"]:
        for cmd in ("ioc", "run"):
            where = w.fresh()
            p = hostile_path(where, kind)
            argv = [cmd, "--out", str(where / ("r.json" if cmd == "ioc" else "results"))]
            out.append(run_cli("paths", f"{cmd} with IOC_BENCH_CACHE {kind}", argv, where, cwd, {"IOC_BENCH_CACHE": p}))
    where = w.fresh()
    long_stem = w.demo(where, "s" * 250 + ".npz")
    out.append(run_cli("paths", "replay: output name too long", ["replay", str(long_stem)], where, cwd))
    return out


def parsers(w: World, cwd: Path) -> list[Outcome]:
    out = []
    configs = {
        "nested list 100": "[" * 100 + "]" * 100,
        "nested list 100000": "[" * 100_000 + "]" * 100_000,
        "nested object 1000": '{"a":' * 1000 + "1" + "}" * 1000,
        "nested value 200": '{"n_random": ' + "[" * 200 + "]" * 200 + "}",
        "100 KB text": '{"n_random": "' + "x" * 100_000 + '"}',
        "1 MB list": '{"n_random": [' + "1," * 500_000 + "1]}",
        "100 KB unknown key": '{"' + "k" * 100_000 + '": 1}',
        "not JSON, 100 KB": "{" * 100_000,
        "int 10**23": '{"n_random": 100000000000000000000000}',
        "int 10**400": '{"n_random": 1' + "0" * 400 + "}",
        "int 10**5000": '{"n_random": 1' + "0" * 5000 + "}",
        "int 2**31": '{"max_iterations": 2147483648}',
        "int -2**40": '{"n_random": -1099511627776}',
        "float 1e23 for int": '{"n_random": 1e23}',
        "float 1e400": '{"perturbation": 1e400}',
        "NaN for int": '{"max_iterations": NaN}',
        "Infinity": '{"perturbation": Infinity}',
        "int beyond float": '{"perturbation": 1' + "0" * 400 + "}",
        "bool for int": '{"forward_starts": true}',
        "array": "[1, 2]",
        "string": '"x"',
    }
    for label, text in configs.items():
        for cmd in ("ioc", "run"):
            where = w.fresh()
            argv = [cmd, "--config", text, "--out", str(where / ("r.json" if cmd == "ioc" else "results"))]
            out.append(run_cli("parsers", f"{cmd} --config {label}", argv, where, cwd))
    for suite in ("nope", "", "smoke ", "../x", "x" * 10_000):
        for extra in ([], ["--json"]):
            where = w.fresh()
            out.append(run_cli("parsers", f"run --list --suite {suite[:12]!r} {' '.join(extra)}",
                               ["run", "--list", "--suite", suite, *extra], where, cwd))  # fmt: skip
    for name in ("nope", "../x", "x" * 10_000, "log-barrier\n", "", "é"):
        for cmd in ("ioc", "run"):
            where = w.fresh()
            argv = [cmd, "--algorithm", name, "--out", str(where / ("r.json" if cmd == "ioc" else "results"))]
            out.append(run_cli("parsers", f"{cmd} --algorithm {name[:12]!r}", argv, where, cwd))
    for label, meta in _demo_metas(w).items():
        where = w.fresh()
        path = where / "d.npz"
        _spoil_demo(w.demo_bytes, path, meta)
        out.append(run_cli("parsers", f"replay: meta {label}", ["replay", str(path)], where, cwd))
    for value in ("1e999", "-1", "nan", "0", "1" + "0" * 5000, "x" * 100_000):
        where = w.fresh()
        out.append(run_cli("parsers", f"gait --speed {value[:10]}", ["gait", "--speed", value], where, cwd))
    return out


def _demo_metas(w: World) -> dict[str, Callable[[dict], str]]:
    def with_(**changes):
        return lambda meta: json.dumps(meta | changes)

    return {
        "nested 100000": lambda meta: '{"schema": 2, "gait": ' + "[" * 100_000 + "]" * 100_000 + "}",
        "nested 500 in task": lambda meta: json.dumps(meta | {"task": {"speed": [[[[[[[[0.27]]]]]]]]}})
        .replace("[[[[", "[" * 250, 1)
        .replace("]]]]", "]" * 250, 1),
        "n_intervals 10**30": with_(n_intervals=10**30),
        "speed 10**400": with_(task={"speed": 10**400, "step_length": None}),
        "speed -1": with_(task={"speed": -1, "step_length": None}),
        "weight 10**400": lambda meta: json.dumps(meta | {"weights": meta["weights"] | {"hip": 10**400}}),
        "feature huge int": lambda meta: json.dumps(meta | {"features": meta["features"] | {"hip": 10**400}}),
        "100 KB model name": with_(model="m" * 100_000),
        "params a list": with_(params=[1, 2]),
        "multistart best 10**30": lambda meta: json.dumps(
            meta | {"multistart": {"best": 10**30, "starts": (meta.get("multistart") or {}).get("starts", [])}}
        ),
    }  # fmt: skip


def _spoil_demo(good: bytes, path: Path, meta_change: Callable[[dict], str]) -> None:
    with np.load(io.BytesIO(good)) as data:
        arrays = {k: data[k] for k in data.files}
    arrays["meta"] = np.array(meta_change(json.loads(str(arrays["meta"]))))
    np.savez(path, **arrays)


def api(w: World, cwd: Path) -> list[Outcome]:
    from ioc_bench import Demonstration, Task, optimize_gait
    from ioc_bench.runner.leaderboard import write_leaderboard
    from ioc_bench.runner.results import load_results, read_result
    from ioc_bench.runner.run import run_cases
    from ioc_bench.synthetic.case import CaseSpec
    from ioc_bench.synthetic.results import parse_result
    from ioc_bench.viz.figures import make_figures

    out = []
    for value in (10**400, -(10**400), float("nan"), float("inf"), 0, -1, True, np.True_, "0.27", None, [0.27],
                  np.float32("nan"), np.float64(-0.1), complex(1, 0)):  # fmt: skip
        where = w.fresh()
        out.append(run_api("api", f"Task({str(value)[:16]})", lambda v=value: Task(v), where))
        length = (lambda v=value: Task(0.27, step_length=v)) if value is not None else (lambda: Task(-1))
        out.append(run_api("api", f"Task(0.27, step_length={str(value)[:16]})", length, where))
    for value in (None, 5, 1.5, b"x.npz", ["x.npz"], {"path": "x"}, "", "/dev/zero", "/dev/urandom",
                  "/proc/self/environ", "/etc/passwd", "/"):  # fmt: skip
        where = w.fresh()
        out.append(
            run_api("api", f"Demonstration.load({str(value)[:20]})", lambda v=value: Demonstration.load(v), where)
        )
    where = w.fresh()
    os.mkfifo(where / "f.npz")
    out.append(run_api("api", "Demonstration.load(<FIFO>)", lambda: Demonstration.load(where / "f.npz"), where))
    kwargs = [
        {"params": "walker"}, {"params": {"leg_mass": 1}}, {"model": "walker"}, {"model": 5}, {"rules": "paper"},
        {"rules": {}}, {"task": 0.27}, {"task": "fast"}, {"init": "x.npz"}, {"guesses": "x.npz"},
        {"guesses": [1]}, {"guesses": 5}, {"starts": 10**9}, {"starts": 0}, {"starts": 1.5}, {"workers": 10**9},
        {"seed": -1}, {"seed": "0"}, {"n_intervals": 10**9}, {"verify": "yes"}, {"on_start_done": 5},
        {"weights": "nope"}, {"weights": [np.nan, 1, 1]}, {"weights": {"bogus": 1}},
    ]  # fmt: skip
    for kw in kwargs:
        where = w.fresh()
        out.append(run_api("api", f"optimize_gait({kw})", lambda kw=kw: optimize_gait(**kw), where))
    identity = ("algorithm", "seed", "weight_set", "condition", "config", "case_key", "case_config")
    for field, value in [(f, v) for f, v in _spoils(w.record) if f not in identity][:40]:
        where = w.fresh()
        out.append(run_api("api", f"parse_result({field}={str(value)[:16]})",
                           lambda f=field, v=value: parse_result(w.record | {f: v}), where))  # fmt: skip
    for node in ("fifo", "link:/dev/zero", "dir"):
        where = w.fresh()
        res = w.results(where, node=node)
        out.append(run_api("api", f"load_results(<{node}>)", lambda r=res: load_results(r), where))
        file = res / "log-barrier" / "nominal__ideal__seed0.json"
        out.append(run_api("api", f"read_result(<{node}>)", lambda f=file: read_result(f), where))
    spec = [CaseSpec("log-barrier", "nominal", "ideal", 0)]
    for kind in PATH_KINDS:
        where = w.fresh()
        p = hostile_path(where, kind)
        out.append(run_api("api", f"run_cases(out={kind})", lambda p=p: run_cases(spec, p), where))
        res = w.results(where)
        board = load_results(res)
        out.append(
            run_api("api", f"write_leaderboard(out={kind})", lambda p=p, b=board: write_leaderboard(b, p), where)
        )
        out.append(run_api("api", f"make_figures(out={kind})", lambda p=p, r=res: make_figures(r, p), where))
    return out


CLASSES = [("security", security), ("result files", trusted_results), ("paths", late_paths), ("parsers", parsers),
           ("api", api)]  # fmt: skip


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--verbose", action="store_true", help="print every input with its message")
    args = parser.parse_args()

    from ioc_bench import optimize_gait
    from ioc_bench.runner.results import write_result
    from ioc_bench.synthetic.case import CaseSpec

    sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))
    from conftest import synthetic_result  # the tests' plausible result, without running anything

    t0 = time.perf_counter()
    demo = optimize_gait("nominal", starts=1, workers=1)  # the only solve, before the trap is set
    _set_traps()
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        demo_bytes = demo.save(tmp / "good.npz").read_bytes()
        write_result(tmp / "r", CaseSpec("log-barrier", "nominal", "ideal", 0), synthetic_result())
        record = json.loads((tmp / "r" / "log-barrier" / "nominal__ideal__seed0.json").read_text())
        os.environ["IOC_BENCH_CACHE"] = str(tmp / "cache")
        world = World(tmp / "world", demo_bytes, record)
        world.root.mkdir()
        cwd = tmp / "cwd"
        cwd.mkdir()
        os.chdir(cwd)
        outcomes = [o for _, make in CLASSES for o in make(world, cwd)]
        os.chdir(tmp.parent)
    by_class = defaultdict(list)
    for o in outcomes:
        by_class[o.klass].append(o)
    print("| class | inputs | handled |\n|---|---|---|")
    for klass, group in by_class.items():
        print(f"| {klass} | {len(group)} | {sum(o.handled for o in group)} |")
    print(f"| all | {len(outcomes)} | {sum(o.handled for o in outcomes)} |")
    print(f"\n({time.perf_counter() - t0:.0f} s)")
    for o in outcomes:
        if not o.handled or args.verbose:
            mark = "ok  " if o.handled else "MISS"
            print(f"{mark} [{o.klass}] {o.label}: {o.why or o.message[:160]}")
    return 0 if all(o.handled for o in outcomes) else 1


def _set_traps() -> None:
    """Replace everything that solves with a trap: an input that reaches it was checked too late."""
    from ioc_bench.runner import run as runner
    from ioc_bench.trajopt.forward_problem import ForwardProblem

    def trap(*args, **kwargs):
        raise _Trap()

    runner.prepare_inputs = trap
    ForwardProblem.solve = trap  # every solve, whoever asks
    ForwardProblem.__init__ = trap  # and every build


if __name__ == "__main__":
    raise SystemExit(main())
