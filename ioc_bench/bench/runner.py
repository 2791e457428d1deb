"""Run many cases in parallel, one result file per finished case, resumable.

Everything is checked before any expensive work (:func:`plan_run`): the cases, the
executor (a Ray cluster must answer), the time limit, the results directory and the
result files already in it. Then :meth:`RunPlan.run` holds the results directory (a
lock; temporaries of killed writers removed), prepares the demonstrations, and runs the
cases on the executor (:mod:`ioc_bench.bench.executor`). The runner alone writes result
files, atomically, as each case finishes: interrupting the run (Ctrl-C, a killed worker,
a killed runner) loses no finished case.

Running the same command again skips every case whose file holds a success. A failed
case (its algorithm failed, it timed out, its worker died) is recorded and shown, and
retried on the next run unless ``keep_failed`` is set.
"""

from __future__ import annotations

import os
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path

from ioc_bench.bench.case import CaseResult, CaseSpec
from ioc_bench.bench.demos import DemoRequest, check_cache, demonstration
from ioc_bench.bench.executor import (
    DEFAULT_TIME_LIMIT,
    Executor,
    Job,
    check_time_limit,
    get_executor,
    schedule,
)
from ioc_bench.bench.results import (
    ResultFileError,
    check_not_held,
    results_directory,
    stored_result,
    write_result,
)
from ioc_bench.demo import Demonstration
from ioc_bench.fileio import check_output_dir
from ioc_bench.ioc.registry import get_algorithm, make_algorithm

OnCase = Callable[[CaseSpec, CaseResult], None]

__all__ = ["DEFAULT_TIME_LIMIT", "RunPlan", "RunSummary", "plan_run", "prepare_demonstrations", "run_cases"]


@dataclass(frozen=True)
class RunSummary:
    """What a run did: cases skipped as already done, run now (of which retried after an
    earlier failure), and failed now (incl. timeouts)."""

    total: int
    skipped: int
    ran: int
    failed: int
    wall_time: float
    retried: int = 0


@dataclass
class RunPlan:
    """A checked run, ready to go: see :func:`plan_run`."""

    specs: list[CaseSpec]
    out: Path
    executor: Executor
    time_limit: float
    keep_failed: bool

    def pending(self) -> tuple[list[CaseSpec], int]:
        """The cases to run now and how many of them are retries of failed ones.

        Raises :class:`ResultFileError` if a case's file exists but is not a result
        (it is never overwritten).
        """
        pending, retries = [], 0
        for spec in self.specs:
            stored = stored_result(self.out, spec)
            if stored is None:
                pending.append(spec)
            elif stored.failed and not self.keep_failed:
                pending.append(spec)
                retries += 1
        return pending, retries

    def run(self, on_case: OnCase | None = None, on_stage: Callable[[str], None] | None = None) -> RunSummary:
        """Run every pending case; ``on_case(spec, result)`` after each is written."""
        t0 = time.perf_counter()
        say = on_stage or (lambda _msg: None)
        failed = [0]

        def finish(spec: CaseSpec, result: CaseResult) -> None:
            write_result(self.out, spec, result)
            failed[0] += result.failed
            if on_case:
                on_case(spec, result)

        with results_directory(self.out):
            pending, retries = self.pending()
            if pending:
                demos = prepare_demonstrations(pending, say)
                retried = f" ({retries} retried after failing before)" if retries else ""
                for name in sorted({spec.algorithm for spec in pending}):
                    get_algorithm(name).prepare()  # shared set-up, built once before workers fork
                say(f"running {len(pending)} case(s){retried}")
                jobs = [_job(spec, demos) for spec in pending]
                schedule(self.executor, jobs, self.time_limit, finish)
        total = len(self.specs)
        return RunSummary(total, total - len(pending), len(pending), failed[0], time.perf_counter() - t0, retries)


def plan_run(
    specs: Sequence[CaseSpec],
    out: str | os.PathLike,
    workers: int | None = None,
    time_limit: float = DEFAULT_TIME_LIMIT,
    executor: str = "local",
    address: str | None = None,
    keep_failed: bool = False,
) -> RunPlan:
    """Check a run before any expensive work; ``ValueError`` (one line) for anything wrong.

    Checks that every case's algorithm exists and accepts its config, the time limit, the
    executor (``local`` or ``ray``; a Ray cluster must answer), that ``out`` can be a
    results directory, that every result file already there for these cases reads, and
    that the demonstration cache can be used.
    """
    specs = list(specs)
    for spec in specs:
        if not isinstance(spec, CaseSpec):
            raise ValueError(f"expected CaseSpec items, got {type(spec).__name__}")
        make_algorithm(spec.algorithm, **spec.config)
    plan = RunPlan(
        specs=specs,
        out=check_output_dir(out),
        executor=get_executor(executor, workers=workers, address=address),
        time_limit=check_time_limit(time_limit),
        keep_failed=bool(keep_failed),
    )
    if plan.out.is_dir():
        check_not_held(plan.out)
        try:
            plan.pending()
        except ResultFileError as exc:
            raise ResultFileError(f"{exc} (move it away, or use another --out)") from None
    plan.executor.check()
    check_cache()
    return plan


def run_cases(
    specs: Sequence[CaseSpec],
    out: str | os.PathLike,
    workers: int | None = None,
    time_limit: float = DEFAULT_TIME_LIMIT,
    executor: str = "local",
    address: str | None = None,
    on_case: OnCase | None = None,
    on_stage: Callable[[str], None] | None = None,
    keep_failed: bool = False,
) -> RunSummary:
    """Check and run every case of ``specs`` not yet done in ``out``; see the module docstring."""
    return plan_run(specs, out, workers, time_limit, executor, address, keep_failed).run(on_case, on_stage)


def prepare_demonstrations(
    specs: Sequence[CaseSpec], say: Callable[[str], None] | None = None
) -> dict[DemoRequest, Demonstration]:
    """The demonstrations of every case, each once: the one it observes (its multi-start seed
    is the case's seed) and the one its cost is tested at; solved (all cores) or read from
    the cache."""
    requests = [r for s in specs for r in s.demo_requests()] + [s.transfer_request() for s in specs]
    unique = list(dict.fromkeys(r for r in requests if r is not None))
    if say:
        say(f"preparing {len(unique)} demonstration(s)")
    return {request: demonstration(request) for request in unique}


def _job(spec: CaseSpec, demos: dict[DemoRequest, Demonstration]) -> Job:
    first, *others = (demos[r] for r in spec.demo_requests())
    request = spec.transfer_request()
    return Job(spec, first, None if request is None else demos[request], tuple(others))
