"""The ``local`` executor: one forked worker process per case on this machine.

The parent builds the trajectory solver before forking, so workers start at once. Each
worker runs one case and sends its result back through a pipe; the parent (the runner)
writes it. A worker that dies without reporting becomes a failed result with its exit
code; workers die with the parent however it dies (:mod:`ioc_bench.processes`), so a killed
run leaves no orphaned cases (a worker's death is logged at WARNING to
``ioc_bench.runner.process_pool``).
Each worker's numpy BLAS gets this machine's cores divided among the workers: unlimited,
two workers with two BLAS threads each on 2 cores ran inverse-kkt's dense least squares
2-3x slower (docs/performance.md, "Parallel cases and BLAS threads"). CasADi's own
OpenBLAS (IPOPT's MUMPS) is not limited.
"""

from __future__ import annotations

import contextlib
import itertools
import logging
import multiprocessing as mp
import os
from dataclasses import dataclass
from multiprocessing.connection import Connection, wait

from threadpoolctl import threadpool_limits

from ioc_bench.processes import die_with_parent
from ioc_bench.runner.executor import Job, execute, failure_of
from ioc_bench.runner.protocol import Record
from ioc_bench.runner.results import parse_any
from ioc_bench.trajopt.forward_problem import get_forward_problem
from ioc_bench.validation import check_count

logger = logging.getLogger(__name__)


@dataclass
class _Worker:
    job: Job
    process: mp.Process
    conn: Connection


class ProcessPool:
    """Forked worker processes, at most ``workers`` at a time (default: all cores)."""

    def __init__(self, workers: int | None = None, address: str | None = None):
        if address is not None:
            raise ValueError("--address is for the ray executor; the local executor runs on this machine")
        self.workers = check_count(workers, "workers", optional=True) or os.cpu_count() or 1
        self._blas_threads = max(1, (os.cpu_count() or 1) // self.workers)  # each worker's share
        self._running: dict[int, _Worker] = {}
        self._ids = itertools.count()
        self._ctx: mp.context.BaseContext | None = None

    def check(self) -> None:
        """Nothing to check: this machine can always fork."""

    def start(self) -> int:
        get_forward_problem()  # built once here, inherited by every forked worker
        self._ctx = mp.get_context("fork" if "fork" in mp.get_all_start_methods() else "spawn")
        return self.workers

    def submit(self, job: Job) -> int:
        assert self._ctx is not None, "start() first"
        parent, child = self._ctx.Pipe(duplex=False)
        process = self._ctx.Process(target=_work, args=(child, job, self._blas_threads, os.getpid()), daemon=True)
        process.start()
        child.close()
        handle = next(self._ids)
        self._running[handle] = _Worker(job, process, parent)
        return handle

    def poll(self, timeout: float) -> list[tuple[int, Record]]:
        workers = list(self._running.values())
        wait([w.conn for w in workers] + [w.process.sentinel for w in workers], timeout=timeout)
        done = []
        for handle, worker in list(self._running.items()):
            result = _collect(worker)
            if result is not None:
                del self._running[handle]
                done.append((handle, result))
        return done

    def cancel(self, handle: int) -> None:
        worker = self._running.pop(handle, None)
        if worker is not None:
            worker.process.kill()
            worker.process.join()
            worker.conn.close()

    def stop(self) -> None:
        for handle in list(self._running):
            self.cancel(handle)


def _work(conn: Connection, job: Job, blas_threads: int, parent_pid: int) -> None:
    die_with_parent(parent_pid)  # no orphaned case, and Ctrl-C is the parent's to handle
    with threadpool_limits(limits=blas_threads), contextlib.suppress(BrokenPipeError):
        conn.send(execute(job).to_dict())
    conn.close()


def _collect(worker: _Worker) -> Record | None:
    """The worker's result if it reported or died, else None (still running). Whether the
    process is alive is read before the pipe: a worker that has exited has written all it
    will, so a report sent before it died is read, not taken for a death. A worker that ended
    without a report is one failure, whether its pipe shows the end or not (a sibling forked
    while it ran may hold the pipe open)."""
    alive = worker.process.is_alive()
    if worker.conn.poll():
        try:
            data = worker.conn.recv()
        except (EOFError, OSError):
            data = None
        worker.process.join()
        worker.conn.close()
        if data is not None:
            return parse_any(data)
        return _died(worker)
    if not alive:
        worker.process.join()
        worker.conn.close()
        return _died(worker)
    return None


def _died(worker: _Worker) -> Record:
    """The failed record of a worker that exited without reporting (joined), logged."""
    code = worker.process.exitcode
    logger.warning(
        "worker %s of case %s exited with code %s before reporting", worker.process.pid, worker.job.spec.key, code
    )
    return failure_of(worker.job.spec, f"worker exited with code {code} before reporting")
