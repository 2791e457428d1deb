"""``optimize_gait``: the optimal step for given weights, as a :class:`Demonstration`.

This is the forward problem every other part of ioc-bench calls: the benchmark to make
demonstrations, IOC algorithms (through their oracles) to test candidate weights.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence

import numpy as np

from ioc_bench.checks import check_count, check_seed
from ioc_bench.demo import Demonstration
from ioc_bench.features import ALL_FEATURES, evaluate
from ioc_bench.model.params import WalkerParams
from ioc_bench.model.walker import walker_linkage
from ioc_bench.task import Task
from ioc_bench.trajopt.gait_nlp import DEFAULT_INTERVALS
from ioc_bench.trajopt.initial_guess import perturbed_step, rough_step
from ioc_bench.trajopt.multistart import pick_best, solve_starts
from ioc_bench.trajopt.solver import SolveResult, StartPoint, get_solver
from ioc_bench.weights import WeightSpec, parse_weights

#: The paper's number of starts.
DEFAULT_STARTS = 15


def optimize_gait(
    weights: WeightSpec = "nominal",
    params: WalkerParams | None = None,
    task: Task | None = None,
    starts: int = DEFAULT_STARTS,
    seed: int = 0,
    init: Demonstration | None = None,
    guesses: Sequence[Demonstration] = (),
    workers: int | None = None,
    n_intervals: int = DEFAULT_INTERVALS,
    on_start_done: Callable[[int, int], None] | None = None,
) -> Demonstration:
    """Optimize the periodic step for ``weights``; returns the best feasible optimum found.

    Args:
        weights: a name of ``WEIGHT_SETS``, numbers over (hip, knee, dtau) or over all six
            features, or a mapping from feature name to weight. Normalised to unit norm.
        params: the walker model (default: SPEC section 1).
        task: the task (default: speed 0.27).
        starts: multi-start size: start 0 is the rough periodic guess, the others perturb
            it with noise drawn from ``seed``. Ignored when ``init`` is given.
        seed: seed of the start perturbations; the same seed gives the same optimum.
        init: warm-start a single solve from this demonstration's primal-dual solution.
        guesses: demonstrations whose trajectories are tried as extra (cold) starts, e.g.
            other weight sets' optima.
        workers: processes for the multi-start (default: all cores).
        n_intervals: Hermite-Simpson intervals.
        on_start_done: called as ``(done, total)`` after each start finishes.

    Returns:
        The demonstration, whose ``solver`` reports status, violation, iterations and time
        of the chosen solve and whose ``multistart`` summarises every start. If no start is
        feasible it is still returned, with ``solver.success`` False.

    Raises:
        ValueError: bad input (weights, a ``task`` that is not a :class:`Task`, an ``init``
            that is not a :class:`Demonstration`, counts below 1, a negative seed), before
            any solve.
    """
    params = _instance(params, WalkerParams, "params", "WalkerParams()") or WalkerParams()
    task = _instance(task, Task, "task", "Task(speed=0.27)") or Task()
    w = _weights(weights)
    starts = check_count(starts, "starts")
    seed = check_seed(seed)
    workers = check_count(workers, "workers", optional=True)
    n_intervals = check_count(n_intervals, "n_intervals")
    init = _instance(init, Demonstration, "init", "Demonstration.load(path)")
    guesses = [_instance(g, Demonstration, "each of guesses", "Demonstration.load(path)") for g in guesses]
    if on_start_done is not None and not callable(on_start_done):
        raise ValueError(f"on_start_done must be callable, got {on_start_done!r}")
    solver = get_solver(n_intervals)
    if init is not None:
        start = StartPoint(solver.decision_vector(init.trajectory), *_duals(init, solver))
        result = solver.solve(start, params, task.speed, w)
        return _demonstration(result, w, params, task, None, n_intervals)
    origins, points = _start_points(params, task, starts, seed, guesses, solver, n_intervals)
    done = [0]

    def progress(_i: int, _r: SolveResult) -> None:
        done[0] += 1
        if on_start_done:
            on_start_done(done[0], len(points))

    results = solve_starts(points, params, task.speed, w, n_intervals, workers, progress)
    best, summary = pick_best(results, origins)
    return _demonstration(results[best], w, params, task, summary, n_intervals)


def _instance(value: object, cls: type, what: str, example: str):
    """``value`` if it is None or a ``cls``; else a ``ValueError`` showing how to make one."""
    if value is not None and not isinstance(value, cls):
        raise ValueError(f"{what} must be a {cls.__name__} (e.g. {example}), got {type(value).__name__} {value!r:.60}")
    return value


def _weights(spec: WeightSpec) -> np.ndarray:
    """Unit weights over ALL_FEATURES (three numbers or a set name leave distractors at 0)."""
    return parse_weights(spec, ALL_FEATURES)


def _duals(init: Demonstration, solver) -> tuple[np.ndarray | None, np.ndarray | None]:
    n_x, n_g = solver.nlp.layout.size, len(solver.nlp.constraints.lb)
    if init.lam_x.shape == (n_x,) and init.lam_g.shape == (n_g,):
        return init.lam_x, init.lam_g
    return None, None


def _start_points(params, task, starts, seed, guesses, solver, n_intervals):
    linkage = walker_linkage(params)
    n_knots = 2 * n_intervals + 1
    layout = solver.nlp.layout
    origins = ["rough guess"]
    points = [StartPoint(layout.pack(rough_step(linkage, params, task.speed, n_knots)))]
    for i in range(1, starts):
        rng = np.random.default_rng([seed, i])
        points.append(StartPoint(layout.pack(perturbed_step(linkage, params, task.speed, n_knots, rng))))
        origins.append(f"perturbed (seed {seed}, start {i})")
    for j, demo in enumerate(guesses):
        points.append(StartPoint(solver.decision_vector(demo.trajectory)))
        origins.append(f"guess {j}: weights {_fmt(demo.weight_vector)}")
    return origins, points


def _fmt(w: np.ndarray) -> str:
    return "(" + ", ".join(f"{x:.3g}" for x in w) + ")"


def _demonstration(result: SolveResult, w, params, task, summary, n_intervals) -> Demonstration:
    features = evaluate(result.trajectory, walker_linkage(params), ALL_FEATURES)
    return Demonstration(
        trajectory=result.trajectory,
        weights={f: float(x) for f, x in zip(ALL_FEATURES, w)},
        features=features,
        params=params,
        task=task,
        solver=result.report,
        multistart=summary,
        n_intervals=n_intervals,
        lam_x=result.lam_x,
        lam_g=result.lam_g,
    )
