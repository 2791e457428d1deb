"""Run many cases in parallel, one result file per finished case, resumable.

Local runs fork one worker process per case (at most ``workers`` at a time) from a parent
that has built the trajectory solver, so workers start at once. The parent alone writes
result files, atomically, as each case finishes: interrupting the run (Ctrl-C, a killed
worker, a killed parent) loses no finished case, and running the same command again
skips every case whose file exists. A case over its time limit is killed and recorded
as failed with the reason; the run goes on. ``executor="ray"`` sends the same cases to
a Ray cluster (optional extra: ``pip install 'ioc-bench[ray]'``).
"""

from __future__ import annotations

import contextlib
import ctypes
import multiprocessing as mp
import os
import signal
import sys
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from multiprocessing.connection import Connection, wait

from ioc_bench.bench.case import CaseResult, failure, run_case
from ioc_bench.bench.conditions import get_condition
from ioc_bench.bench.demos import demonstration
from ioc_bench.bench.results import CaseSpec, is_done, write_result
from ioc_bench.demo import Demonstration
from ioc_bench.trajopt.solver import get_solver
from ioc_bench.weights import parse_weights

#: Default per-case time limit, seconds.
DEFAULT_TIME_LIMIT = 1800.0

OnCase = Callable[[CaseSpec, CaseResult], None]


@dataclass(frozen=True)
class RunSummary:
    """What a run did: cases skipped as already done, run now, failed (incl. timeouts)."""

    total: int
    skipped: int
    ran: int
    failed: int
    wall_time: float


def run_cases(
    specs: Sequence[CaseSpec],
    out: str | os.PathLike,
    workers: int | None = None,
    time_limit: float = DEFAULT_TIME_LIMIT,
    executor: str = "local",
    address: str | None = None,
    on_case: OnCase | None = None,
    on_stage: Callable[[str], None] | None = None,
) -> RunSummary:
    """Run every case of ``specs`` not yet done in ``out``; see the module docstring."""
    t0 = time.perf_counter()
    pending = [s for s in specs if not is_done(out, s)]
    say = on_stage or (lambda _msg: None)
    failed = [0]

    def finish(spec: CaseSpec, result: CaseResult) -> None:
        write_result(out, spec, result)
        failed[0] += result.failed
        if on_case:
            on_case(spec, result)

    if pending:
        say(f"preparing {len(_demo_keys(pending))} demonstration(s)")
        demos = prepare_demonstrations(pending)
        say(f"running {len(pending)} case(s)")
        if executor == "local":
            _run_local(pending, demos, workers or os.cpu_count() or 1, time_limit, finish)
        elif executor == "ray":
            from ioc_bench.bench.ray_executor import run_ray

            run_ray(pending, demos, workers, time_limit, address, finish)
        else:
            raise ValueError(f"unknown executor {executor!r}; valid: local, ray")
    return RunSummary(len(specs), len(specs) - len(pending), len(pending), failed[0], time.perf_counter() - t0)


def _demo_keys(specs: Sequence[CaseSpec]) -> dict[tuple, CaseSpec]:
    keys: dict[tuple, CaseSpec] = {}
    for s in specs:
        keys.setdefault((s.weight_set, get_condition(s.condition).demo_speed), s)
    return keys


def prepare_demonstrations(specs: Sequence[CaseSpec]) -> dict[tuple, Demonstration]:
    """The true demonstration of every case, solved (all cores) or read from the cache."""
    return {
        key: demonstration(parse_weights(spec.weight_set), task=get_condition(spec.condition).demo_task())
        for key, spec in _demo_keys(specs).items()
    }


def demo_for(spec: CaseSpec, demos: dict[tuple, Demonstration]) -> Demonstration:
    return demos[(spec.weight_set, get_condition(spec.condition).demo_speed)]


def execute(spec: CaseSpec, demo: Demonstration | None) -> CaseResult:
    """Run one case; infrastructure errors become failed results too."""
    try:
        return run_case(spec.algorithm, spec.weight_set, spec.condition, spec.seed, spec.config, demo=demo)
    except Exception as exc:  # e.g. an unknown algorithm inside a worker
        return failure(spec.algorithm, spec.weight_set, spec.condition, spec.seed, f"{type(exc).__name__}: {exc}")


# -- local process pool ----------------------------------------------------------------


def _worker(conn: Connection, spec: CaseSpec, demo: Demonstration) -> None:
    _die_with_parent()
    signal.signal(signal.SIGINT, signal.SIG_IGN)  # the parent decides what to do on Ctrl-C
    with contextlib.suppress(BrokenPipeError):
        conn.send(execute(spec, demo).to_dict())
    conn.close()


def _die_with_parent() -> None:
    """Ask Linux to kill this worker if the parent dies (no orphaned cases)."""
    if sys.platform.startswith("linux"):
        with contextlib.suppress(OSError, AttributeError):
            ctypes.CDLL("libc.so.6").prctl(1, signal.SIGKILL)  # PR_SET_PDEATHSIG


@dataclass
class _Running:
    spec: CaseSpec
    process: mp.Process
    conn: Connection
    started: float


Finish = Callable[[CaseSpec, CaseResult], None]


def _run_local(pending: list[CaseSpec], demos: dict, workers: int, time_limit: float, finish: Finish) -> None:
    get_solver()  # built once here, inherited by every forked worker
    ctx = mp.get_context("fork" if "fork" in mp.get_all_start_methods() else "spawn")
    queue, running = list(pending), []
    try:
        while queue or running:
            while queue and len(running) < workers:
                running.append(_start(ctx, queue.pop(0), demos))
            wait([r.conn for r in running] + [r.process.sentinel for r in running], timeout=0.5)
            for r in list(running):
                result = _collect(r, time_limit)
                if result is not None:
                    running.remove(r)
                    finish(r.spec, result)
    finally:
        for r in running:
            r.process.kill()
            r.process.join()


def _start(ctx, spec: CaseSpec, demos: dict) -> _Running:
    parent, child = ctx.Pipe(duplex=False)
    process = ctx.Process(target=_worker, args=(child, spec, demo_for(spec, demos)), daemon=True)
    process.start()
    child.close()
    return _Running(spec, process, parent, time.monotonic())


def _collect(r: _Running, time_limit: float) -> CaseResult | None:
    """The case's result if it finished (or failed, or timed out), else None."""
    if r.conn.poll():
        try:
            data = r.conn.recv()
        except (EOFError, OSError):
            data = None
        r.process.join()
        if data is not None:
            return CaseResult.from_dict(data)
        return _fail(r.spec, f"worker exited with code {r.process.exitcode} before reporting")
    if not r.process.is_alive():
        return _fail(r.spec, f"worker died (exit code {r.process.exitcode})")
    if time.monotonic() - r.started > time_limit:
        r.process.kill()
        r.process.join()
        return _fail(r.spec, f"timed out after {time_limit:g} s")
    return None


def _fail(spec: CaseSpec, reason: str) -> CaseResult:
    return failure(spec.algorithm, spec.weight_set, spec.condition, spec.seed, reason)
