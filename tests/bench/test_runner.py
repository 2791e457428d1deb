"""The suite runner: resumable after a kill, failed cases retried, checks before work, executors."""

from __future__ import annotations

import dataclasses
import json
import os
import signal
import subprocess
import sys
import time

import pytest

import ioc_bench
from ioc_bench.ioc import registry
from ioc_bench.ioc.algorithm import IOCAlgorithm
from ioc_bench.runner import run as runner
from ioc_bench.runner.executor import EXECUTORS, Job, failure_of, get_executor, schedule
from ioc_bench.runner.results import ResultFileError, load_results, read_result, write_result
from ioc_bench.runner.run import run_cases
from ioc_bench.synthetic.case import CaseSpec
from ioc_bench.synthetic.suites import get_suite

#: A quick configuration of the paper's method, enough to exercise the runner.
QUICK = {"n_random": 1, "max_iterations": 2}


def _files(root):
    return sorted(p.relative_to(root).as_posix() for p in root.rglob("*") if p.is_file())


def test_smoke_suite_killed_midway_resumes_and_retries_a_failed_case(tmp_path, ideal_nominal_cached):
    """The smoke suite as `ioc-bench run` runs it (default algorithm and config): killed midway,
    resumed; then one case's file is replaced by a failure, which the next run retries (and
    ``--keep-failed`` keeps)."""
    out = tmp_path / "results"
    cmd = [sys.executable, "-m", "ioc_bench.cli", "run", "--suite", "smoke", "--out", str(out), "--workers", "2"]
    first = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, env=os.environ.copy())
    deadline = time.monotonic() + 600
    while time.monotonic() < deadline and not list(out.rglob("*.json")):
        time.sleep(0.2)
    first.send_signal(signal.SIGKILL)
    first.wait()
    done_before = {p: p.read_bytes() for p in out.rglob("*.json")}
    assert 1 <= len(done_before) < 4, "the kill should land midway"
    rerun = subprocess.run(cmd, capture_output=True, text=True, env=os.environ.copy())
    assert rerun.returncode == 0, rerun.stderr
    assert "| log-barrier | walker |" in rerun.stdout  # it ends by printing the leaderboard (its grid)
    files = _files(out)
    assert len(files) == 4 and all(f.endswith(".json") for f in files)  # no duplicates, no temporaries
    for path, content in done_before.items():
        assert path.read_bytes() == content  # finished cases were not run again
    specs = get_suite("smoke").cases("log-barrier")
    assert sorted(f"{s.key}.json" for s in specs) == files
    assert not any(r.failed for r in load_results(out))

    # A failed case (here: a worker that died) is recorded, shown, kept on request, and retried by default.
    results = {s.key: read_result(s.path(out)) for s in specs}
    victim = min(specs, key=lambda s: results[s.key].wall_time)
    write_result(out, victim, failure_of(victim, "worker died (exit code -9)"))
    before = {p: p.read_bytes() for p in out.rglob("*.json")}
    stale = victim.path(out).parent / f".{victim.path(out).name}.abc123.tmp"
    stale.write_text('{"half": ')  # what a writer killed mid-write could leave without O_TMPFILE
    kept = subprocess.run([*cmd, "--keep-failed"], capture_output=True, text=True, env=os.environ.copy())
    assert kept.returncode == 0, kept.stderr
    assert "0 run, 4 already done" in kept.stderr and "1 case(s) failed" in kept.stderr
    assert f"{victim.key}: worker died (exit code -9)" in kept.stderr  # each failure is listed with its reason
    assert {p: p.read_bytes() for p in out.rglob("*.json")} == before
    assert not stale.exists()  # temporaries of killed writers are removed when a run starts
    retried = subprocess.run(cmd, capture_output=True, text=True, env=os.environ.copy())
    assert retried.returncode == 0, retried.stderr
    assert "1 run (1 of them retried), 3 already done, 0 failed" in retried.stderr
    again = read_result(victim.path(out))
    assert not again.failed and again.weights == results[victim.key].weights  # same seed, same answer
    for path, content in before.items():
        if path != victim.path(out):
            assert path.read_bytes() == content
    assert _files(out) == files


@pytest.fixture
def dying_algorithm(monkeypatch):
    """An algorithm whose worker process dies in the middle of ``fit``."""
    monkeypatch.setattr(registry, "_REGISTRY", dict(registry._REGISTRY))

    class Dies(IOCAlgorithm):
        description = "exits its process"

        def fit(self, problem):
            os._exit(3)

    ioc_bench.register_algorithm("dies-test")(Dies)
    return "dies-test"


def test_timeouts_and_dead_workers_are_recorded_then_retried(tmp_path, ideal_nominal_cached, dying_algorithm):
    specs = [
        CaseSpec("log-barrier", "nominal", "ideal", 0, {"n_random": 3, "max_iterations": 25}),
        CaseSpec(dying_algorithm, "nominal", "ideal", 0),
    ]
    summary = run_cases(specs, tmp_path, workers=2, time_limit=2.0)
    results = {r.algorithm: r for r in load_results(tmp_path)}
    assert summary.ran == 2 and summary.failed == 2 and summary.retried == 0
    assert "timed out after 2 s" in results["log-barrier"].reason
    assert "worker exited with code 3 before reporting" in results[dying_algorithm].reason
    assert results["log-barrier"].config["n_random"] == 3  # a failure records the case's config
    kept = run_cases(specs, tmp_path, workers=2, time_limit=2.0, keep_failed=True)
    assert (kept.ran, kept.skipped) == (0, 2)
    again = run_cases(specs, tmp_path, workers=2, time_limit=2.0)
    assert (again.ran, again.retried, again.failed) == (2, 2, 2)


@pytest.fixture
def no_demonstrations(monkeypatch):
    """Fail the test if a run gets as far as preparing demonstrations."""

    def forbidden(_specs):
        raise AssertionError("expensive work started before the input was checked")

    monkeypatch.setattr(runner, "prepare_inputs", forbidden)


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({"executor": "nope"}, "unknown executor 'nope'; valid: local, ray"),
        ({"time_limit": 0}, "time limit must be a positive number"),
        ({"time_limit": float("nan")}, "time limit must be a positive number"),
        ({"workers": 0}, "workers must be an integer >= 1"),
        ({"address": "127.0.0.1:6379"}, "--address is for the ray executor"),
    ],
)
def test_bad_run_settings_are_refused_before_any_work(tmp_path, no_demonstrations, kwargs, message):
    spec = CaseSpec("log-barrier", "nominal", "ideal", 0)
    with pytest.raises(ValueError, match=message):
        run_cases([spec], tmp_path / "out", **kwargs)
    assert not (tmp_path / "out").exists()


def test_an_unreadable_result_file_is_refused_and_kept(tmp_path, no_demonstrations):
    spec = CaseSpec("log-barrier", "nominal", "ideal", 0)
    spec.path(tmp_path).parent.mkdir(parents=True)
    spec.path(tmp_path).write_text("null")
    with pytest.raises(ResultFileError, match=r"expected a JSON object, got null.*move it away"):
        run_cases([spec], tmp_path)
    assert spec.path(tmp_path).read_text() == "null"


def test_an_output_location_under_a_file_is_refused(tmp_path, no_demonstrations):
    (tmp_path / "file").write_text("x")
    with pytest.raises(ValueError, match="is not a directory"):
        run_cases([CaseSpec("log-barrier", "nominal", "ideal", 0)], tmp_path / "file" / "results")


def test_a_ray_cluster_that_does_not_answer_is_one_line_before_any_work(tmp_path, no_demonstrations):
    pytest.importorskip("ray")
    with pytest.raises(ValueError, match=r"cannot reach a Ray cluster at 127\.0\.0\.1:9") as exc:
        run_cases([CaseSpec("log-barrier", "nominal", "ideal", 0)], tmp_path, executor="ray", address="127.0.0.1:9")
    assert "\n" not in str(exc.value)


def test_a_ray_cluster_that_never_answers_is_one_line_after_the_deadline(tmp_path, no_demonstrations, monkeypatch):
    """A listener that accepts connections and says nothing: the client would wait (or, with a
    wrong token, retry) for ever; the check gives up after its deadline with one line."""
    pytest.importorskip("ray")
    import socket

    from ioc_bench.runner import ray_executor

    monkeypatch.setattr(ray_executor, "CONNECT_TIMEOUT", 4.0)
    with socket.socket() as silent:
        silent.bind(("127.0.0.1", 0))
        silent.listen(16)
        address = f"127.0.0.1:{silent.getsockname()[1]}"
        spec = CaseSpec("log-barrier", "nominal", "ideal", 0)
        expected = r"could not join the Ray cluster at .* within 4 s; .*RAY_AUTH_TOKEN"
        with pytest.raises(ValueError, match=expected) as exc:
            run_cases([spec], tmp_path, executor="ray", address=address)
    assert "\n" not in str(exc.value)


def test_executors_are_looked_up_by_name():
    assert set(EXECUTORS) == {"local", "ray"}
    assert type(get_executor("local", workers=2)).__name__ == "ProcessPool"
    assert type(get_executor("ray")).__name__ == "RayExecutor"


# -- the scheduler: one queue and one time limit for every executor -----------------------------


class FakeExecutor:
    """Finishes jobs after a given number of polls (None: never), records what it was told."""

    def __init__(self, polls_needed: dict[int, int | None], slots: int = 2):
        self.polls_needed, self.slots = polls_needed, slots
        self.running: dict[int, list] = {}
        self.cancelled: list[int] = []
        self.stopped = False
        self.max_in_flight = 0

    def check(self) -> None:
        pass

    def start(self) -> int:
        return self.slots

    def submit(self, job: Job) -> int:
        self.running[job.spec.seed] = [job, 0]
        self.max_in_flight = max(self.max_in_flight, len(self.running))
        return job.spec.seed

    def poll(self, timeout: float):
        time.sleep(min(timeout, 0.01))
        done = []
        for seed, entry in list(self.running.items()):
            entry[1] += 1
            need = self.polls_needed[seed]
            if need is not None and entry[1] >= need:
                del self.running[seed]
                done.append((seed, _success(entry[0].spec)))
        return done

    def cancel(self, handle: int) -> None:
        self.cancelled.append(handle)
        self.running.pop(handle, None)

    def stop(self) -> None:
        self.stopped = True


def _success(spec):
    return dataclasses.replace(failure_of(spec, ""), status="converged")


def _jobs(n):
    return [Job(CaseSpec("log-barrier", "nominal", "ideal", seed), None) for seed in range(n)]


def test_schedule_limits_jobs_in_flight_times_out_stuck_ones_and_finishes_each_once():
    executor = FakeExecutor({0: 1, 1: None, 2: 3, 3: 1}, slots=2)
    finished = []
    schedule(executor, _jobs(4), time_limit=0.3, finish=lambda spec, result: finished.append((spec.seed, result)))
    assert sorted(seed for seed, _ in finished) == [0, 1, 2, 3]  # each exactly once
    by_seed = dict(finished)
    assert by_seed[1].failed and by_seed[1].reason == "timed out after 0.3 s"
    assert not any(by_seed[s].failed for s in (0, 2, 3))
    assert executor.cancelled == [1] and executor.max_in_flight == 2 and executor.stopped


def test_an_error_while_recording_a_success_stops_the_run_and_is_never_recorded_as_a_failure():
    """An error while recording a success must not turn it into a failure written over it."""
    executor = FakeExecutor({0: 1, 1: None}, slots=2)
    recorded = []

    def finish(spec, result):
        if not result.failed:
            raise OSError("disk full")
        recorded.append(result)  # pragma: no cover - must not happen

    with pytest.raises(OSError, match="disk full"):
        schedule(executor, _jobs(2), time_limit=60, finish=finish)
    assert recorded == [] and executor.cancelled == [1] and executor.stopped


def test_ray_gives_the_same_scores_as_the_process_pool(tmp_path, ideal_nominal_cached):
    pytest.importorskip("ray")
    specs = [CaseSpec("log-barrier", "nominal", "ideal", s, QUICK) for s in (0, 1)]
    run_cases(specs, tmp_path / "local", workers=2)
    run_cases(specs, tmp_path / "ray", workers=2, executor="ray")
    local = {(r.seed): r for r in load_results(tmp_path / "local")}
    ray = {(r.seed): r for r in load_results(tmp_path / "ray")}
    assert set(local) == set(ray) == {0, 1}
    for seed in local:
        assert ray[seed].weights == local[seed].weights
        assert ray[seed].weight_error == local[seed].weight_error
        assert ray[seed].n_solves == local[seed].n_solves


def test_result_files_name_their_config(tmp_path, make_result):
    spec = CaseSpec("log-barrier", "nominal", "ideal", 0, QUICK)
    path = write_result(tmp_path, spec, make_result(config=QUICK))
    assert json.loads(path.read_text())["case_config"] == QUICK and path.name.startswith("nominal__ideal__seed0__cfg")
