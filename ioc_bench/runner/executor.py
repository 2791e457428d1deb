"""Executors: where the cases of a run execute, behind one protocol, looked up by name.

An :class:`Executor` only starts jobs, reports the finished ones and cancels the ones
it is told to; :func:`schedule` owns the queue, how many jobs are in flight and the
per-case time limit, for every executor alike. Built in:

- ``local``: forked worker processes on this machine (:mod:`ioc_bench.runner.process_pool`);
- ``ray``: tasks on a Ray cluster (:mod:`ioc_bench.runner.ray_executor`, optional extra).

Executors are registered as ``"module:Class"`` strings and imported only when asked
for, so Ray is never imported by a local run. Whatever goes wrong with a job (its
worker dies, its Ray task fails, it runs over the time limit) becomes the case's failed
record with the reason: a run never stops for one case.

:func:`schedule` logs each case it starts (INFO) and each it cancels for running over
the time limit (WARNING) to ``ioc_bench.runner.executor``.
"""

from __future__ import annotations

import importlib
import logging
import time
from collections import deque
from collections.abc import Callable, Hashable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any, Protocol

from ioc_bench.ioc.registry import make_algorithm
from ioc_bench.runner.protocol import Case, Record
from ioc_bench.validation import one_line

#: Default per-case time limit, seconds.
DEFAULT_TIME_LIMIT = 1800.0
#: How long :func:`schedule` waits for a job to finish before checking time limits again.
POLL_SECONDS = 0.5
#: Executors by name: ``"module:Class"``, imported on first use.
EXECUTORS: dict[str, str] = {
    "local": "ioc_bench.runner.process_pool:ProcessPool",
    "ray": "ioc_bench.runner.ray_executor:RayExecutor",
}

Finish = Callable[[Case, Record], None]

logger = logging.getLogger(__name__)


@dataclass(frozen=True, eq=False)
class Job:
    """One case to run with the inputs it needs, prepared by the runner (shipped along, so
    workers need no shared disk)."""

    spec: Case
    inputs: Mapping[Hashable, Any] = field(default_factory=dict)


class Executor(Protocol):
    """Runs jobs somewhere. Made with ``(workers, address)``; used by :func:`schedule` only.

    ``check`` is called before any expensive work and raises ``ValueError`` (one line) if
    the executor cannot run here (e.g. Ray missing or its cluster unreachable). ``start``
    returns how many jobs may run at once. ``poll`` waits up to ``timeout`` seconds and
    returns the jobs finished since the last call, as (handle, result), never a job that
    was cancelled. ``stop`` releases everything; it is called however the run ends.
    """

    def check(self) -> None: ...

    def start(self) -> int: ...

    def submit(self, job: Job) -> Hashable: ...

    def poll(self, timeout: float) -> list[tuple[Hashable, Record]]: ...

    def cancel(self, handle: Hashable) -> None: ...

    def stop(self) -> None: ...


def get_executor(name: str, workers: int | None = None, address: str | None = None) -> Executor:
    """The executor registered as ``name``; ``ValueError`` listing the valid names otherwise."""
    if name not in EXECUTORS:
        raise ValueError(f"unknown executor {name!r}; valid: {', '.join(EXECUTORS)}")
    module, attr = EXECUTORS[name].split(":")
    return getattr(importlib.import_module(module), attr)(workers=workers, address=address)


def check_time_limit(time_limit: float) -> float:
    """``time_limit`` if it is a positive number of seconds (``inf``: none), else ``ValueError``."""
    if isinstance(time_limit, bool) or not isinstance(time_limit, (int, float)) or not time_limit > 0:
        raise ValueError(f"time limit must be a positive number of seconds, got {time_limit!r}")
    return float(time_limit)


def schedule(executor: Executor, jobs: Sequence[Job], time_limit: float, finish: Finish) -> None:
    """Run ``jobs`` on a started-here ``executor``; ``finish(spec, result)`` once per job.

    At most as many jobs as ``executor.start()`` allows are in flight; a job running
    longer than ``time_limit`` seconds (counted from its submission) is cancelled and
    recorded as failed. ``finish`` is called exactly once per job and its errors (e.g.
    a full disk) stop the run; they are never recorded as the case's failure.
    """
    slots = executor.start()
    queue = deque(jobs)
    running: dict[Hashable, tuple[Job, float]] = {}
    try:
        while queue or running:
            while queue and len(running) < slots:
                job = queue.popleft()
                running[executor.submit(job)] = (job, time.monotonic())
                logger.info("case %s started", job.spec.key)
            for handle, result in executor.poll(POLL_SECONDS):
                job, _ = running.pop(handle)
                finish(job.spec, result)
            now = time.monotonic()
            for handle, (job, started) in list(running.items()):
                if now - started > time_limit:
                    logger.warning("case %s ran over the time limit of %g s; cancelled", job.spec.key, time_limit)
                    executor.cancel(handle)
                    del running[handle]
                    finish(job.spec, failure_of(job.spec, f"timed out after {time_limit:g} s"))
    finally:
        for handle in running:
            executor.cancel(handle)
        executor.stop()


def execute(job: Job) -> Record:
    """Run one case (in a worker); errors outside the algorithm become failed results too."""
    try:
        return job.spec.run(job.inputs)
    except Exception as exc:  # e.g. a plugin that is not installed on a Ray node, a data file gone
        return failure_of(job.spec, f"{type(exc).__name__}: {one_line(str(exc))}")


def failure_of(spec: Case, reason: str) -> Record:
    """The failed record of ``spec`` with ``reason``, carrying the case's effective config."""
    try:
        config = make_algorithm(spec.algorithm, **spec.config).config_dict()
    except ValueError:  # the algorithm is not available here: keep what identifies the case
        config = dict(spec.config)
    return spec.failure(reason, config)
