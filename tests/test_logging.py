"""What library calls report goes through the ``ioc_bench`` loggers, never straight to stdout or stderr."""

from __future__ import annotations

import logging
import multiprocessing as mp
import os
import subprocess
import sys
import time
from types import SimpleNamespace

import pytest

from ioc_bench.cli import main
from ioc_bench.model.params import WalkerParams
from ioc_bench.runner.executor import Job, failure_of
from ioc_bench.runner.results import write_result
from ioc_bench.runner.run import RunPlan
from ioc_bench.synthetic.demos import DemoRequest, demonstration
from ioc_bench.synthetic.suites import get_suite
from ioc_bench.task import Task
from ioc_bench.weights import parse_weights


def _messages(caplog, logger: str, level: int) -> list[str]:
    return [r.getMessage() for r in caplog.records if r.name == logger and r.levelno == level]


def test_the_package_logger_has_a_null_handler_and_no_other():
    logger = logging.getLogger("ioc_bench")
    assert any(isinstance(h, logging.NullHandler) for h in logger.handlers)
    assert all(isinstance(h, logging.NullHandler) for h in logger.handlers)  # a library never configures output
    assert logger.level == logging.NOTSET


class _Executor:
    """Finishes every job at its first poll with a made-up result; the case named ``dies`` fails."""

    def __init__(self, make_result, dies: str):
        self.make_result, self.dies = make_result, dies
        self.running: dict[str, Job] = {}

    def check(self) -> None:
        pass

    def start(self) -> int:
        return 2

    def submit(self, job: Job) -> str:
        self.running[job.spec.key] = job
        return job.spec.key

    def poll(self, timeout: float):
        done = []
        for key, job in list(self.running.items()):
            spec = job.spec
            if key == self.dies:
                result = failure_of(spec, "worker exited with code 3 before reporting")
            else:
                result = self.make_result(spec.algorithm, spec.weight_set, spec.condition, spec.seed)
            done.append((key, result))
            del self.running[key]
        return done

    def cancel(self, handle: str) -> None:
        self.running.pop(handle, None)

    def stop(self) -> None:
        pass


def test_a_run_logs_its_stages_and_each_case_and_prints_nothing(tmp_path, make_result, monkeypatch, caplog, capsys):
    """A run of the smoke suite with one case already done and one that fails (no solve: the
    demonstrations are not made and the executor makes its results up)."""
    monkeypatch.setattr(DemoRequest, "prepare", lambda self: None)
    specs = get_suite("smoke").cases("log-barrier")
    done, dies, *ok = specs
    write_result(tmp_path, done, make_result(done.algorithm, done.weight_set, done.condition, done.seed))
    plan = RunPlan(specs, tmp_path, _Executor(make_result, dies.key), time_limit=60.0, keep_failed=False)
    stages = []
    with caplog.at_level(logging.INFO, logger="ioc_bench"):
        summary = plan.run(on_stage=stages.append)
    assert (summary.ran, summary.skipped, summary.failed) == (3, 1, 1)

    info = _messages(caplog, "ioc_bench.runner.run", logging.INFO)
    assert f"1 of 4 case(s) already done in {tmp_path}" in info
    assert stages and all(stage in info for stage in stages)  # the callback still gets every stage, and the log too
    assert stages[0].startswith("preparing ") and stages[-1] == "running 3 case(s)"
    for spec in ok:
        assert f"case {spec.key}: weight error 0.0100, 2 s" in info
    assert info[-1].startswith("run finished: 3 run, 1 already done, 1 failed, ")
    warnings = _messages(caplog, "ioc_bench.runner.run", logging.WARNING)
    assert warnings == [f"case {dies.key}: FAILED (worker exited with code 3 before reporting), 0 s"]
    started = _messages(caplog, "ioc_bench.runner.executor", logging.INFO)
    assert sorted(started) == sorted(f"case {spec.key} started" for spec in [dies, *ok])
    assert capsys.readouterr() == ("", "")


def test_a_run_logs_nothing_below_warning_unless_asked(tmp_path, make_result, monkeypatch, caplog):
    monkeypatch.setattr(DemoRequest, "prepare", lambda self: None)
    specs = get_suite("smoke").cases("log-barrier")
    plan = RunPlan(specs, tmp_path, _Executor(make_result, specs[0].key), time_limit=60.0, keep_failed=False)
    with caplog.at_level(logging.WARNING, logger="ioc_bench"):
        plan.run()
    assert [(r.name, r.levelname) for r in caplog.records] == [("ioc_bench.runner.run", "WARNING")]


def test_a_worker_that_dies_is_logged_as_a_warning(caplog):
    from ioc_bench.runner import process_pool
    from ioc_bench.synthetic.case import CaseSpec

    spec = CaseSpec("log-barrier", "nominal", "ideal", 0)
    ctx = mp.get_context("fork")
    parent, child = ctx.Pipe(duplex=False)
    process = ctx.Process(target=os._exit, args=(3,), daemon=True)
    process.start()
    child.close()
    worker = process_pool._Worker(Job(spec), process, parent)
    with caplog.at_level(logging.WARNING, logger="ioc_bench"):
        deadline = time.monotonic() + 30
        while (result := process_pool._collect(worker)) is None and time.monotonic() < deadline:
            time.sleep(0.01)
    assert result is not None and result.reason == "worker exited with code 3 before reporting"
    [record] = caplog.records
    assert record.name == "ioc_bench.runner.process_pool" and record.levelno == logging.WARNING
    assert record.getMessage() == f"worker {process.pid} of case {spec.key} exited with code 3 before reporting"


def test_a_demonstration_logs_its_solve_cache_hit_and_a_broken_entry(
    tmp_path, monkeypatch, caplog, capsys, nominal_demo
):
    monkeypatch.setenv("IOC_BENCH_CACHE", str(tmp_path))
    solves = []
    monkeypatch.setattr(DemoRequest, "solve", lambda self, workers=None: solves.append(self) or nominal_demo)
    request = DemoRequest(parse_weights("nominal"), WalkerParams(), Task(0.27), seed=0, starts=1)
    name = "ioc_bench.synthetic.demos"

    with caplog.at_level(logging.DEBUG, logger="ioc_bench"):
        demonstration(request)
    info = _messages(caplog, name, logging.INFO)
    assert len(info) == 2 and info[0].startswith(f"solving demonstration {request.key}: walker weights [")
    assert "at speed 0.27, 1 start(s), seed 0" in info[0]
    assert info[1].startswith(f"demonstration {request.key} solved in ")

    caplog.clear()
    with caplog.at_level(logging.DEBUG, logger="ioc_bench"):
        demonstration(request)
    assert len(solves) == 1
    assert [(r.levelno, r.getMessage()) for r in caplog.records] == [
        (logging.DEBUG, f"demonstration {request.key} read from the cache")
    ]

    entry = tmp_path / "demos" / f"{request.key}.npz"
    entry.write_bytes(b"not a demonstration")
    caplog.clear()
    with caplog.at_level(logging.INFO, logger="ioc_bench"):
        demonstration(request)
    assert len(solves) == 2
    [warning] = _messages(caplog, name, logging.WARNING)
    assert warning.startswith(f"cache entry {entry} cannot be used (") and warning.endswith(
        "; solving the demonstration again"
    )
    assert capsys.readouterr() == ("", "")


def _all_done(tmp_path, make_result) -> list:
    specs = get_suite("smoke").cases("log-barrier")
    for spec in specs:
        write_result(tmp_path, spec, make_result(spec.algorithm, spec.weight_set, spec.condition, spec.seed))
    return specs


def test_the_command_line_prints_the_library_log_only_when_asked(tmp_path, make_result, capsys):
    _all_done(tmp_path, make_result)
    argv = ["run", "--suite", "smoke", "--out", str(tmp_path)]
    assert main(argv) == 0
    plain = capsys.readouterr()
    assert "ioc_bench" not in plain.err and "already done in" not in plain.err  # no log line by default

    assert main(["--log-level", "INFO", *argv]) == 0
    logged = capsys.readouterr()
    assert logged.out == plain.out
    lines = logged.err.splitlines()
    assert f"INFO ioc_bench.runner.run: 4 of 4 case(s) already done in {tmp_path}" in lines
    assert any(line.startswith("INFO ioc_bench.runner.run: run finished: 0 run, 4 already done") for line in lines)
    assert [line for line in lines if not line.startswith("INFO ioc_bench.")] == plain.err.splitlines()
    assert all(isinstance(h, logging.NullHandler) for h in logging.getLogger("ioc_bench").handlers)  # left as found
    assert logging.getLogger("ioc_bench").level == logging.NOTSET

    assert main(["--log-level", "warning", *argv]) == 0
    assert capsys.readouterr().err == plain.err


def test_a_bad_log_level_is_refused_in_one_line(capsys):
    with pytest.raises(SystemExit) as exc:
        main(["--log-level", "loud", "algorithms"])
    err = capsys.readouterr().err
    assert exc.value.code == 2 and err.count("\n") == 1 and "--log-level" in err


def test_a_warning_with_no_logging_configured_prints_nothing(tmp_path):
    """Without the null handler, Python would print a warning with no handler to go to on stderr."""
    code = "import logging, ioc_bench; logging.getLogger('ioc_bench.runner.run').warning('case x: FAILED')"
    env = {**os.environ, "PYTHONPATH": os.pathsep.join(sys.path)}
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env, cwd=tmp_path)
    assert proc.returncode == 0 and (proc.stdout, proc.stderr) == ("", "")


def test_a_reference_step_logs_its_solve_and_an_entry_that_cannot_be_kept(tmp_path, monkeypatch, caplog):
    from ioc_bench.human import case, load_step

    monkeypatch.setenv("IOC_BENCH_CACHE", str(tmp_path))
    solved = SimpleNamespace(to_dict=dict)
    monkeypatch.setattr(case, "solve_step", lambda *args: solved)
    monkeypatch.setattr(case, "atomic_write_json", lambda path, data: (_ for _ in ()).throw(OSError("read-only")))
    request = case.ReferenceStep("nominal", load_step("WBDS01", "T04"), 1, 0)
    with caplog.at_level(logging.INFO, logger="ioc_bench"):
        assert request.prepare() is solved
    got = [(r.name, r.levelno, r.getMessage()) for r in caplog.records]
    assert got[0] == (
        "ioc_bench.human.case",
        logging.INFO,
        f"solving reference step {request.key}: nominal on WBDS01 T04 (walker), 1 start(s), seed 0",
    )
    assert got[1][2].startswith(f"reference step {request.key} solved in ")
    assert got[2] == (
        "ioc_bench.human.case",
        logging.WARNING,
        f"could not keep reference step {request.key} in the cache: read-only",
    )
