"""The suite runner: resumable after a kill, time limits, Ray equals the process pool."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time

import pytest

from ioc_bench.bench.results import CaseSpec, load_results
from ioc_bench.bench.runner import run_cases
from ioc_bench.bench.suites import get_suite

#: A quick configuration of the paper's method, enough to exercise the runner.
QUICK = {"n_random": 1, "max_iterations": 2}


def _files(root):
    return sorted(p.relative_to(root).as_posix() for p in root.rglob("*") if p.is_file())


def test_smoke_suite_killed_midway_resumes_with_every_case_exactly_once(tmp_path, ideal_nominal_cached):
    """The smoke suite as `ioc-bench run` runs it (default algorithm and config)."""
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
    assert "| log-barrier | ideal |" in rerun.stdout  # it ends by printing the leaderboard
    files = _files(out)
    assert len(files) == 4 and all(f.endswith(".json") for f in files)  # no duplicates, no temporaries
    for path, content in done_before.items():
        assert path.read_bytes() == content  # finished cases were not run again
    specs = get_suite("smoke").cases("log-barrier")
    assert sorted(f"{s.key}.json" for s in specs) == files
    assert not any(r.failed for r in load_results(out))


def test_timeout_and_failures_are_recorded_and_the_run_goes_on(tmp_path, ideal_nominal_cached):
    specs = [
        CaseSpec("log-barrier", "nominal", "ideal", 0, {"n_random": 3, "max_iterations": 25}),
        CaseSpec("no-such-algorithm", "nominal", "ideal", 0),
    ]
    summary = run_cases(specs, tmp_path, workers=2, time_limit=2.0)
    results = {r.algorithm: r for r in load_results(tmp_path)}
    assert summary.ran == 2 and summary.failed == 2
    assert "timed out after 2 s" in results["log-barrier"].reason
    assert "unknown algorithm" in results["no-such-algorithm"].reason


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
