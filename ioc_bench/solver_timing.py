"""Solver timing (``ioc-bench solver-timing``): medians of cold, warm and multi-start solves on this machine.

This times the trajectory optimizer only; the IOC benchmark itself is :mod:`ioc_bench.synthetic`.

- cold: one solve from a perturbed rough guess (a different start each repeat);
- warm: from the nominal optimum's primal-dual point, re-solve for weights perturbed by
  about 10 % (what an IOC loop does between iterations);
- multistart: the full ``optimize_gait`` with 15 starts on all cores.
The solver build (once per process) is timed separately and excluded from the others.
"""

from __future__ import annotations

import statistics
import time
from collections.abc import Callable
from dataclasses import asdict, dataclass

import numpy as np

from ioc_bench.model.params import WalkerParams
from ioc_bench.model.walker import WALKER
from ioc_bench.optimize import DEFAULT_STARTS, optimize_gait
from ioc_bench.task import Task
from ioc_bench.trajopt.forward_problem import SolveRequest, get_forward_problem
from ioc_bench.trajopt.initial_guess import perturbed_step
from ioc_bench.trajopt.solution import StartPoint
from ioc_bench.trajopt.step_problem import DEFAULT_INTERVALS
from ioc_bench.weights import full_weights, parse_weights

#: Relative size of the weight perturbation between warm-started solves.
WARM_WEIGHT_NOISE = 0.1


@dataclass(frozen=True)
class SolverTiming:
    """Median wall times (s) and IPOPT iterations of each kind of solve, and how many failed."""

    n_intervals: int
    build_s: float
    cold_median_s: float
    cold_median_iterations: float
    warm_median_s: float
    warm_median_iterations: float
    multistart_median_s: float
    repeats: int
    multistart_repeats: int
    failures: int

    def to_dict(self) -> dict:
        return asdict(self)


def time_solver(
    repeats: int = 7,
    multistart_repeats: int = 3,
    n_intervals: int = DEFAULT_INTERVALS,
    on_progress: Callable[[str], None] | None = None,
) -> SolverTiming:
    """Time the three kinds of solve; see the module docstring."""
    say = on_progress or (lambda _msg: None)
    params, task = WalkerParams(), Task()
    t0 = time.perf_counter()
    forward = get_forward_problem(n_intervals=n_intervals)
    build = time.perf_counter() - t0
    w = full_weights(parse_weights("nominal"), ("hip", "knee", "dtau"))
    cold = []
    for i in range(repeats):
        x0 = forward.step.layout.pack(
            perturbed_step(WALKER, params, task.speed, forward.n_knots, np.random.default_rng([1, i]))
        )
        cold.append(forward.solve(SolveRequest(StartPoint(x0), params, task, w)))
        say(f"cold {i + 1}/{repeats}")
    base = min((r for r in cold if r.report.success), key=lambda r: r.report.objective, default=cold[0])
    rng = np.random.default_rng(2)
    warm = []
    for i in range(repeats):
        wi = w * np.exp(WARM_WEIGHT_NOISE * rng.normal(size=w.shape))
        warm.append(forward.solve(SolveRequest(base.point, params, task, wi / np.linalg.norm(wi))))
        say(f"warm {i + 1}/{repeats}")
    multi = []
    for i in range(multistart_repeats):
        t0 = time.perf_counter()
        optimize_gait("nominal", task=task, starts=DEFAULT_STARTS, seed=i, n_intervals=n_intervals)
        multi.append(time.perf_counter() - t0)
        say(f"multistart {i + 1}/{multistart_repeats}")
    failures = sum(not r.report.success for r in cold + warm)
    return SolverTiming(
        n_intervals=n_intervals,
        build_s=build,
        cold_median_s=statistics.median(r.report.wall_time for r in cold),
        cold_median_iterations=statistics.median(r.report.iterations for r in cold),
        warm_median_s=statistics.median(r.report.wall_time for r in warm),
        warm_median_iterations=statistics.median(r.report.iterations for r in warm),
        multistart_median_s=statistics.median(multi),
        repeats=repeats,
        multistart_repeats=multistart_repeats,
        failures=failures,
    )
