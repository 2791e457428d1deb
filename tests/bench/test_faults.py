"""Faults a cluster scheduler, a full disk or a careless hand inject into a run, and what holds.

Each test injects one fault class of ``docs/faults.md``: a run killed while its workers
run, a cache entry copied over another, a result file edited by hand, two runs on one
folder, a folder moved or replaced during a run, a worker that dies, a full disk.
"""

from __future__ import annotations

import contextlib
import errno
import json
import os
import shutil
import signal
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import numpy as np
import pytest

from ioc_bench.cli import main
from ioc_bench.runner import run as runner
from ioc_bench.runner.results import (
    ResultFileError,
    check_not_held,
    read_result,
    results_directory,
    write_result,
)
from ioc_bench.synthetic.case import CaseSpec
from ioc_bench.synthetic.demos import DemoRequest, ReferenceCache, demonstration, mismatch
from ioc_bench.task import Task
from ioc_bench.trajopt.solution import SolverReport, StartPoint
from ioc_bench.weights import parse_weights

#: Seconds a killed process's workers get to disappear.
GONE_WITHIN = 10.0


def _alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    try:  # a zombie (exited, not yet reaped by its new parent) is gone for our purpose
        return Path(f"/proc/{pid}/stat").read_text().split(")")[-1].split()[0] != "Z"
    except OSError:
        return False


def _wait_gone(pids: list[int], seconds: float = GONE_WITHIN) -> list[int]:
    deadline = time.monotonic() + seconds
    while time.monotonic() < deadline and any(_alive(p) for p in pids):
        time.sleep(0.1)
    return [p for p in pids if _alive(p)]


def _children(pid: int) -> list[int]:
    text = Path(f"/proc/{pid}/task/{pid}/children").read_text()
    return [int(p) for p in text.split()]


pytestmark = pytest.mark.skipif(not sys.platform.startswith("linux"), reason="process faults are checked on Linux")


def test_a_killed_run_leaves_no_worker_and_no_lock_behind(tmp_path):
    """kill -9 of the process holding a results folder: its worker dies with it, and a process
    it forked that lives on (not one of ours) does not keep the folder's lock."""
    script = textwrap.dedent(
        """
        import os, sys, time
        from ioc_bench.runner.results import results_directory
        from ioc_bench.processes import die_with_parent
        with results_directory(sys.argv[1]):
            parent = os.getpid()
            worker = os.fork()
            if worker == 0:
                die_with_parent(parent)
                time.sleep(120)
                os._exit(0)
            bystander = os.fork()
            if bystander == 0:
                time.sleep(120)
                os._exit(0)
            print(worker, bystander, flush=True)
            time.sleep(120)
        """
    )
    proc = subprocess.Popen([sys.executable, "-c", script, str(tmp_path / "res")], stdout=subprocess.PIPE, text=True)
    worker, bystander = (int(p) for p in proc.stdout.readline().split())
    try:
        with pytest.raises(ResultFileError, match="another run is writing"):
            check_not_held(tmp_path / "res")  # held while the run lives
        proc.kill()
        proc.wait()
        assert _wait_gone([worker]) == [], "the worker outlived its run"
        assert _alive(bystander)
        check_not_held(tmp_path / "res")  # the lock went with the run, though a child lives on
    finally:
        for pid in (worker, bystander):
            if _alive(pid):
                os.kill(pid, signal.SIGKILL)


def test_a_worker_whose_parent_died_before_it_asked_exits_at_once():
    """The race of a kill right after a fork: the worker finds its parent gone and exits."""
    script = textwrap.dedent(
        """
        import os, time
        from ioc_bench.processes import die_with_parent
        pid = os.fork()
        if pid == 0:
            null = os.open(os.devnull, os.O_WRONLY)
            os.dup2(null, 1), os.dup2(null, 2)  # the test reads the parent's output only
            time.sleep(0.5)  # the parent is killed in between the fork and the request
            die_with_parent(12345678)  # not this worker's parent any more
            time.sleep(120)
            os._exit(0)
        print(pid, flush=True)
        """
    )
    out = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, check=True)
    pid = int(out.stdout.split()[0])
    assert _wait_gone([pid]) == []


@pytest.mark.slow
def _pool_workers(pid: int) -> list[int]:
    """Children of ``pid`` forked from it (same command line): its pool, not a helper it ran."""
    cmdline = Path(f"/proc/{pid}/cmdline").read_bytes()
    workers = []
    for child in _children(pid):
        with contextlib.suppress(OSError):
            if Path(f"/proc/{child}/cmdline").read_bytes() == cmdline:
                workers.append(child)
    return workers


def _interruptible() -> None:
    """In the child before it runs: Ctrl-C as a terminal delivers it. A shell starts a
    background job with SIGINT ignored and the child would inherit that (then the signal
    these tests send does nothing, whatever the command does with it)."""
    signal.signal(signal.SIGINT, signal.SIG_DFL)


def _start_gait(tmp_path: Path, name: str) -> tuple[subprocess.Popen, list[int]]:
    """``ioc-bench gait`` with a 6-start pool of 2 workers, returned once both workers run."""
    env = os.environ | {"IOC_BENCH_CACHE": str(tmp_path / "cache")}
    cmd = [sys.executable, "-m", "ioc_bench.cli", "gait", "--starts", "6", "--workers", "2"]
    proc = subprocess.Popen(
        [*cmd, "--out", str(tmp_path / name)], env=env, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True,
        preexec_fn=_interruptible,
    )  # fmt: skip
    deadline = time.monotonic() + 120
    while time.monotonic() < deadline and proc.poll() is None and len(_pool_workers(proc.pid)) < 2:
        time.sleep(0.05)
    workers = _pool_workers(proc.pid)
    assert len(workers) >= 2, "the multi-start pool never started"
    return proc, workers


@pytest.mark.parametrize(
    ("sig", "after"),
    [(signal.SIGKILL, 0.0), (signal.SIGINT, 0.0), (signal.SIGINT, 0.5), (signal.SIGINT, 1.5)],
    ids=["kill", "interrupt-at-pool-start", "interrupt-0.5s-in", "interrupt-1.5s-in"],
)
def test_kill_or_interrupt_during_the_multistart_leaves_no_orphan(tmp_path, sig, after):
    """``ioc-bench gait`` killed (SIGKILL) or interrupted (SIGINT) while its pool solves starts:
    no worker outlives it, no output is written, and Ctrl-C is exit code 130 without a traceback.
    The signal is sent only while the pool's workers are seen running (a start takes seconds)."""
    proc, workers = _start_gait(tmp_path, "demo.npz")
    time.sleep(after)
    assert proc.poll() is None and _pool_workers(proc.pid), "the pool ended before the signal: not this test's case"
    os.kill(proc.pid, sig)
    code = proc.wait(timeout=30)
    assert _wait_gone(workers) == [], f"workers outlived {sig!r}"
    if sig == signal.SIGINT:
        stderr = proc.stderr.read()
        assert (code, stderr.strip()) == (130, "interrupted"), stderr
    assert not (tmp_path / "demo.npz").exists()


def test_a_dead_multistart_worker_is_one_clear_error(monkeypatch):
    from ioc_bench.trajopt import multistart
    from ioc_bench.trajopt.forward_problem import ForwardProblem, SolveRequest, get_forward_problem

    forward = get_forward_problem()  # built here; the forked workers inherit the patched solve
    monkeypatch.setattr(ForwardProblem, "solve", lambda self, request: os.kill(os.getpid(), signal.SIGKILL))
    request = SolveRequest(StartPoint(np.zeros(forward.n_x)), None, Task(), np.ones(3))  # never solved
    with pytest.raises(multistart.WorkerDied, match="a multi-start worker died"):
        multistart.solve_starts(forward, [request] * 3, workers=2)


# -- caches trusted by their content, not their name ----------------------------------------------


def test_a_reference_copied_over_another_entry_is_not_taken_for_it(tmp_path):
    cache = ReferenceCache(tmp_path)
    point = StartPoint(np.arange(4.0), np.zeros(4), np.zeros(2))
    report = SolverReport("Solve_Succeeded", True, 0.0, 0.0, 3, 0.1, 1.0)
    cache.put("a" * 24, point, report, 1, 0.5)
    assert cache.get("a" * 24) is not None
    shutil.copy(cache._path("a" * 24), cache._path("b" * 24))  # another observation's file, under b's name
    assert cache.get("b" * 24) is None  # absent: it is computed again, and put replaces the file
    cache.put("b" * 24, point, report, 2, 0.5)
    assert cache.get("b" * 24)[2] == 2


def test_a_stored_reference_of_another_shape_is_computed_again(tmp_path, nominal_demo):
    from ioc_bench.ioc.problem import IOCProblem

    cache = ReferenceCache(tmp_path)
    observed = nominal_demo.trajectory.observed()
    problem = IOCProblem(
        observed, ("hip", "knee", "dtau"), nominal_demo.params, nominal_demo.task, reference_store=cache
    )
    key = problem._reference_key
    report = SolverReport("Solve_Succeeded", True, 0.0, 0.0, 3, 0.1, 1.0)
    cache.put(key, StartPoint(np.arange(4.0), np.zeros(4), np.zeros(2)), report, 1, 0.5)  # its key, wrong content
    reference = problem.reference()
    assert reference.success and problem.stats.calls["project"] >= 1  # solved, not read back
    assert cache.get(key)[0].x.shape == (problem.forward.n_x,)  # and the entry replaced


@pytest.mark.slow
def test_a_demonstration_copied_over_another_entry_is_solved_again_and_replaced(tmp_path, monkeypatch):
    monkeypatch.setenv("IOC_BENCH_CACHE", str(tmp_path))
    weights = parse_weights("nominal")
    seed0 = DemoRequest(weights, _walker(), Task(0.27), seed=0, starts=1)
    seed1 = DemoRequest(weights, _walker(), Task(0.27), seed=1, starts=1)
    first = demonstration(seed0, workers=1)
    entry = tmp_path / "demos" / f"{seed1.key}.npz"
    shutil.copy(tmp_path / "demos" / f"{seed0.key}.npz", entry)  # seed 0's step under seed 1's name
    assert mismatch(seed1, first) == "multi-start seed 0"
    again = demonstration(seed1, workers=1)
    assert again.seed == 1 and not mismatch(seed1, again)
    from ioc_bench.demo import Demonstration

    assert Demonstration.load(entry).seed == 1  # the entry was replaced


def _walker():
    from ioc_bench.model.params import WalkerParams

    return WalkerParams()


# -- result files checked for consistency ---------------------------------------------------------


def _stored(tmp_path: Path, make_result, edit) -> Path:
    spec = CaseSpec("log-barrier", "nominal", "ideal", 0)
    path = write_result(tmp_path, spec, make_result(weight_error=0.12))
    data = json.loads(path.read_text())
    text = edit(data)
    path.write_text(text if isinstance(text, str) else json.dumps(data))
    return path


@pytest.mark.parametrize(
    ("edit", "message"),
    [
        (lambda d: d.update(weight_error=0.5), "is not the mean |weights - true_weights|"),
        (lambda d: d.update(weights=[5, 5, 5]), "unit norm"),
        (lambda d: d.update(found_trajectory_error=1.0), "is not the chosen iteration's trajectory error"),
        (lambda d: d.update(n_solves=99, oracle={"calls": {"optimize": 2, "project": 1}, "forward_solves": 3}),
         "is not the oracle's count"),
        (lambda d: json.dumps(d)[:-1] + ', "seed": 0}', "the key 'seed' twice"),
    ],
)  # fmt: skip
def test_an_edited_result_file_is_refused_naming_what_disagrees(tmp_path, make_result, edit, message):
    path = _stored(tmp_path, make_result, edit)
    with pytest.raises(ResultFileError, match=message.replace("|", r"\|")) as exc:
        read_result(path, tmp_path)
    assert str(path) in str(exc.value) and "\n" not in str(exc.value)


def test_an_unedited_result_file_reads(tmp_path, make_result):
    path = _stored(tmp_path, make_result, lambda d: None)
    assert read_result(path, tmp_path).weight_error == pytest.approx(0.12)


# -- the results folder during a run --------------------------------------------------------------


@pytest.mark.parametrize("replace_with", ["a file", "another folder"])
def test_a_results_folder_moved_or_replaced_mid_run_stops_the_writes(tmp_path, make_result, replace_with):
    root, spec = tmp_path / "res", CaseSpec("log-barrier", "nominal", "ideal", 0)
    with results_directory(root):
        root.rename(tmp_path / "moved")
        (root.write_text("x") if replace_with == "a file" else root.mkdir())
        with pytest.raises(ResultFileError, match="no longer the results folder this run holds"):
            write_result(root, spec, make_result())
    assert not (tmp_path / "moved" / "log-barrier").exists() and (root.is_file() or not any(root.iterdir()))


def test_a_full_disk_is_a_one_line_error_that_leaves_no_partial_file(tmp_path, make_result, monkeypatch):
    from ioc_bench.runner import results

    def full(path, data):
        raise OSError(errno.ENOSPC, "No space left on device", str(path))

    monkeypatch.setattr(results, "atomic_write_json", full)
    with pytest.raises(ResultFileError, match="No space left on device"):
        write_result(tmp_path, CaseSpec("log-barrier", "nominal", "ideal", 0), make_result())
    assert not any(tmp_path.rglob("*.json"))


@pytest.mark.parametrize(
    "fault",
    [
        ResultFileError("another run is writing to res; wait for it or use another --out"),
        OSError(errno.ENOSPC, "No space left on device", "res/x.json"),
        NotADirectoryError(errno.ENOTDIR, "Not a directory", "res/log-barrier"),
    ],
    ids=["lost the lock", "full disk", "folder replaced by a file"],
)
def test_a_fault_during_a_run_is_one_line_and_exit_2(tmp_path, monkeypatch, capsys, fault):
    def run(self, on_case=None, on_stage=None):
        raise fault

    monkeypatch.setattr(runner.RunPlan, "run", run)
    with pytest.raises(SystemExit) as exc:
        main(["run", "--suite", "smoke", "--algorithm", "inverse-kkt", "--out", str(tmp_path / "res")])
    err = capsys.readouterr().err  # the run's progress lines, then its error
    assert exc.value.code == 2 and "Traceback" not in err
    assert (
        err.splitlines()[-1].startswith("ioc-bench run: error: ")
        and str(getattr(fault, "strerror", None) or fault) in err
    )


def test_a_worker_death_in_the_multistart_is_one_line_and_exit_2(tmp_path, monkeypatch, capsys):
    from ioc_bench.trajopt import multistart

    def died(*args, **kwargs):
        raise multistart.WorkerDied("a multi-start worker died (exit code -9); no start was lost on disk")

    monkeypatch.setattr("ioc_bench.optimize.solve_starts", died)
    with pytest.raises(SystemExit) as exc:
        main(["gait", "--starts", "2", "--out", str(tmp_path / "d.npz")])
    err = capsys.readouterr().err
    assert exc.value.code == 2 and len(err.splitlines()) == 1 and "worker died" in err


def test_two_runs_on_one_folder_the_second_is_refused_in_one_line(tmp_path, capsys):
    with results_directory(tmp_path / "res"), pytest.raises(SystemExit) as exc:
        main(["run", "--suite", "smoke", "--algorithm", "inverse-kkt", "--out", str(tmp_path / "res")])
    err = capsys.readouterr().err
    assert exc.value.code == 2 and err.count("\n") == 1 and "another run is writing" in err


def test_the_leaderboard_is_written_beside_its_results_unless_told_otherwise(tmp_path, make_result, capsys):
    spec = CaseSpec("log-barrier", "nominal", "ideal", 0)
    write_result(tmp_path, spec, make_result())
    assert main(["leaderboard", str(tmp_path)]) == 0
    assert (tmp_path / "README.md").is_file() and (tmp_path / "leaderboard.json").is_file()
    assert "replacing" not in capsys.readouterr().out
    assert main(["leaderboard", str(tmp_path)]) == 0
    assert f"(replacing {tmp_path / 'README.md'}" in capsys.readouterr().out
