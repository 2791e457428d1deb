"""Multi-start: solve from many starting points in worker processes, keep the best feasible.

Workers are forked from a parent that has already built the solver, so they start at once
and share nothing mutable; each start is an independent, deterministic IPOPT run, so the
chosen optimum depends only on the starting points (that is, on the seed), never on
scheduling. Ties in cost go to the lowest start index.
"""

from __future__ import annotations

import multiprocessing as mp
import os
from collections.abc import Callable, Sequence
from concurrent.futures import ProcessPoolExecutor, as_completed
from concurrent.futures.process import BrokenProcessPool
from dataclasses import asdict, dataclass
from typing import Any

from ioc_bench.model.catalogue import get_model
from ioc_bench.processes import die_with_parent
from ioc_bench.trajopt.forward_problem import ForwardProblem, SolveRequest, get_forward_problem
from ioc_bench.trajopt.solution import SolveResult, SolverReport

#: Two feasible optima are the same when their costs agree to this relative tolerance.
SAME_OPTIMUM_RTOL = 1e-5


@dataclass(frozen=True)
class StartRecord:
    """One start of a multi-start: where it came from and how its solve went."""

    index: int
    origin: str
    report: SolverReport

    def to_dict(self) -> dict[str, Any]:
        return {"index": self.index, "origin": self.origin} | asdict(self.report)

    @classmethod
    def from_dict(cls, data: dict[str, Any]) -> StartRecord:
        fields = dict(data)
        return cls(int(fields.pop("index")), str(fields.pop("origin")), SolverReport(**fields))


@dataclass(frozen=True)
class MultiStartSummary:
    """The spread of the optima a multi-start found."""

    starts: tuple[StartRecord, ...]
    best: int

    @property
    def feasible(self) -> list[StartRecord]:
        return [s for s in self.starts if s.report.success]

    @property
    def optima(self) -> list[float]:
        """Distinct feasible costs, lowest first."""
        distinct: list[float] = []
        for cost in sorted(s.report.objective for s in self.feasible):
            if not distinct or abs(cost - distinct[-1]) > SAME_OPTIMUM_RTOL * abs(distinct[-1]):
                distinct.append(cost)
        return distinct

    def describe(self) -> str:
        optima = self.optima
        if not optima:
            return f"{len(self.starts)} starts, none feasible"
        spread = (optima[-1] - optima[0]) / optima[0] * 100
        return (
            f"{len(self.starts)} starts, {len(self.feasible)} feasible, {len(optima)} distinct optima "
            f"(cost {optima[0]:.6g} .. {optima[-1]:.6g}, spread {spread:.1f} %), best from start {self.best}"
        )


@dataclass(frozen=True, eq=False)
class _Job:
    """One start's solve, as sent to a worker (the forward problem by name and feature basis:
    workers have it built)."""

    model: str
    n_intervals: int
    request: SolveRequest
    features: tuple[str, ...] | None = None


def _solve_one(job: _Job) -> SolveResult:
    return get_forward_problem(get_model(job.model), job.n_intervals, job.features).solve(job.request)


def solve_starts(
    forward: ForwardProblem,
    requests: Sequence[SolveRequest],
    workers: int | None = None,
    on_done: Callable[[int, SolveResult], None] | None = None,
) -> list[SolveResult]:
    """Solve every request, in ``workers`` processes (default: all cores)."""
    workers = min(len(requests), workers or os.cpu_count() or 1)
    jobs = [_Job(forward.model.name, forward.n_intervals, r, forward.basis) for r in requests]
    results: list[SolveResult | None] = [None] * len(jobs)
    if workers <= 1:
        for i, job in enumerate(jobs):
            results[i] = _solve_one(job)
            if on_done:
                on_done(i, results[i])
        return results  # type: ignore[return-value]
    get_forward_problem(forward.model, forward.n_intervals, forward.basis)  # build once here; forked workers inherit it
    pool = ProcessPoolExecutor(workers, _context(), initializer=die_with_parent, initargs=(os.getpid(),))
    try:
        futures = {pool.submit(_solve_one, job): i for i, job in enumerate(jobs)}
        for fut in as_completed(futures):
            i = futures[fut]
            results[i] = fut.result()
            if on_done:
                on_done(i, results[i])
    except BrokenProcessPool:
        raise WorkerDied(f"a multi-start worker died ({_exit_codes(pool)}); no start was lost on disk") from None
    finally:
        _stop(pool)
    return results  # type: ignore[return-value]


class WorkerDied(RuntimeError):
    """A multi-start worker process died (killed, or out of memory) before it reported."""


def _exit_codes(pool: ProcessPoolExecutor) -> str:
    codes = sorted({p.exitcode for p in (pool._processes or {}).values() if p.exitcode not in (None, 0)})
    return "exit code " + ", ".join(map(str, codes)) if codes else "no exit code"


def _stop(pool: ProcessPoolExecutor) -> None:
    """Stop the pool now, whatever is still running (an interrupt must not wait for the starts)."""
    processes = list((pool._processes or {}).values())
    pool.shutdown(wait=False, cancel_futures=True)
    for process in processes:
        if process.is_alive():
            process.kill()
    for process in processes:
        process.join()


def pick_best(results: Sequence[SolveResult], origins: Sequence[str]) -> tuple[int, MultiStartSummary]:
    """Index of the cheapest feasible result (lowest index on ties; least violation if none)."""
    if any(r.report.success for r in results):
        best = min((r.report.objective, i) for i, r in enumerate(results) if r.report.success)[1]
    else:
        best = min((r.report.max_violation, i) for i, r in enumerate(results))[1]
    records = tuple(StartRecord(i, o, r.report) for i, (o, r) in enumerate(zip(origins, results)))
    return best, MultiStartSummary(records, best)


def _context() -> mp.context.BaseContext:
    """Fork where available (workers inherit the built solver), else spawn."""
    methods = mp.get_all_start_methods()
    return mp.get_context("fork" if "fork" in methods else "spawn")
