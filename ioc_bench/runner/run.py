"""Run many cases in parallel, one result file per finished case, resumable.

Everything is checked before any expensive work (:func:`plan_run`): the cases, the
executor (a Ray cluster must answer), the time limit, the results directory and the
result files already in it. Then :meth:`RunPlan.run` holds the results directory (a
lock; temporaries of killed writers removed), prepares the inputs the cases share
(demonstrations, reference steps), and runs the cases on the executor
(:mod:`ioc_bench.runner.executor`). The runner alone writes result files, atomically,
as each case finishes: interrupting the run (Ctrl-C, a killed worker, a killed runner)
loses no finished case.

Running the same command again skips every case whose file holds a success. A failed
case (its algorithm failed, it timed out, its worker died) is recorded and shown, and
retried on the next run unless ``keep_failed`` is set.

Progress is logged to ``ioc_bench.runner.run`` (besides the ``on_case`` and
``on_stage`` callbacks): each stage and each finished case at INFO, a failed case at
WARNING.
"""

from __future__ import annotations

import logging
import os
import time
from collections.abc import Callable, Hashable, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from ioc_bench.cache import check_cache
from ioc_bench.ioc.registry import get_algorithm, make_algorithm
from ioc_bench.paths import check_output_dir
from ioc_bench.runner.executor import (
    DEFAULT_TIME_LIMIT,
    Executor,
    Job,
    check_time_limit,
    get_executor,
    schedule,
)
from ioc_bench.runner.protocol import Case, Record
from ioc_bench.runner.results import (
    ResultFileError,
    check_not_held,
    results_directory,
    stored_result,
    write_result,
)

OnCase = Callable[[Case, Record], None]

logger = logging.getLogger(__name__)

__all__ = ["DEFAULT_TIME_LIMIT", "RunPlan", "RunSummary", "plan_run", "prepare_inputs", "run_cases"]


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

    specs: list[Case]
    out: Path
    executor: Executor
    time_limit: float
    keep_failed: bool

    def pending(self) -> tuple[list[Case], int]:
        """The cases to run now and how many of them are retries of failed ones.

        Raises :class:`ResultFileError` if a case's file exists but is not a result
        (it is never overwritten).
        """
        pending, retries = [], 0
        for spec, stored in self.stored():
            if stored is None:
                pending.append(spec)
            elif stored.failed and not self.keep_failed:
                pending.append(spec)
                retries += 1
        return pending, retries

    def stored(self) -> list[tuple[Case, Record | None]]:
        """Every case with the record already stored for it (None if there is none yet)."""
        return [(spec, stored_result(self.out, spec)) for spec in self.specs]

    def run(self, on_case: OnCase | None = None, on_stage: Callable[[str], None] | None = None) -> RunSummary:
        """Run every pending case; ``on_case(spec, result)`` after each is written."""
        t0 = time.perf_counter()
        say = _stages(on_stage)
        failed = [0]

        def finish(spec: Case, result: Record) -> None:
            write_result(self.out, spec, result)
            spec.write_extras(self.out, result)
            failed[0] += result.failed
            level = logging.WARNING if result.failed else logging.INFO
            logger.log(level, "case %s: %s, %.0f s", spec.key, result.headline(), result.wall_time)
            if on_case:
                on_case(spec, result)

        with results_directory(self.out):
            pending, retries = self.pending()
            if len(pending) < len(self.specs):
                logger.info(
                    "%d of %d case(s) already done in %s", len(self.specs) - len(pending), len(self.specs), self.out
                )
            for spec, stored in self.stored():  # what a run killed between a record and its figures left out
                if stored is not None:
                    spec.write_extras(self.out, stored)
            if pending:
                inputs = prepare_inputs(pending, on_stage)
                retried = f" ({retries} retried after failing before)" if retries else ""
                for name in sorted({spec.algorithm for spec in pending}):
                    get_algorithm(name).prepare()  # shared set-up, built once before workers fork
                say(f"running {len(pending)} case(s){retried}")
                jobs = [_job(spec, inputs) for spec in pending]
                schedule(self.executor, jobs, self.time_limit, finish)
        total = len(self.specs)
        summary = RunSummary(total, total - len(pending), len(pending), failed[0], time.perf_counter() - t0, retries)
        logger.info(
            "run finished: %d run, %d already done, %d failed, %.0f s",
            summary.ran,
            summary.skipped,
            summary.failed,
            summary.wall_time,
        )
        return summary


def plan_run(
    specs: Sequence[Case],
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
        if not all(hasattr(spec, name) for name in ("key", "needs", "run", "failure", "track")):
            raise ValueError(f"expected cases (of a track: the case protocol's), got {type(spec).__name__}")
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
    specs: Sequence[Case],
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


def run_one(spec: Case, out: str | os.PathLike | None, say: Callable[[str], None] | None = None) -> Record:
    """One case: with ``out``, run as a suite's case (locked, resumed if already there, its
    record and extras written atomically; on this machine's cores); without, in this process,
    writing nothing. ``ValueError`` for bad input, before any solve."""
    if out is None:
        inputs = prepare_inputs([spec], say)
        _stages(say)(f"running {spec.key}")
        record = spec.run(inputs)
        level = logging.WARNING if record.failed else logging.INFO
        logger.log(level, "case %s: %s, %.0f s", spec.key, record.headline(), record.wall_time)
        return record
    plan = plan_run([spec], out, workers=1)
    plan.run(on_stage=say)
    stored = stored_result(plan.out, spec)
    assert stored is not None  # the run wrote it, or it was there
    return stored


def prepare_inputs(specs: Sequence[Case], say: Callable[[str], None] | None = None) -> dict[Hashable, Any]:
    """The inputs of every case, each once (demonstrations, reference steps): read from the
    cache where its entry is that input's, else solved (all cores)."""
    unique = list(dict.fromkeys(r for spec in specs for r in spec.needs()))
    if unique:
        _stages(say)(f"preparing {len(unique)} input(s) (demonstrations, reference steps)")
    return {request: request.prepare() for request in unique}


def _stages(say: Callable[[str], None] | None) -> Callable[[str], None]:
    """``say``, and each stage message logged at INFO too."""

    def stage(msg: str) -> None:
        logger.info("%s", msg)
        if say:
            say(msg)

    return stage


def _job(spec: Case, inputs: Mapping[Hashable, Any]) -> Job:
    return Job(spec, {request: inputs[request] for request in spec.needs()})
