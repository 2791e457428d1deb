"""``optimize_gait``: the optimal step for given weights, as a :class:`Demonstration`.

This is the forward problem every other part of ioc-bench calls: the benchmark to make
demonstrations, IOC algorithms (through their oracles) to test candidate weights. Every
step it returns has been checked for being a local minimum of its own cost (and polished
until it is, see :mod:`ioc_bench.trajopt.local_minimum`), and carries its gait figures.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import replace

import numpy as np

from ioc_bench.demo import Demonstration
from ioc_bench.features import evaluate, model_features
from ioc_bench.model.gait_model import GaitModel, GaitParams
from ioc_bench.model.walker import WALKER
from ioc_bench.task import Task
from ioc_bench.trajopt.forward_problem import ForwardProblem, SolveRequest, basis_key, get_forward_problem
from ioc_bench.trajopt.gait_figures import solved_gait_figures
from ioc_bench.trajopt.initial_guess import multistart_guesses
from ioc_bench.trajopt.local_minimum import verify_local_minimum
from ioc_bench.trajopt.multistart import pick_best, solve_starts
from ioc_bench.trajopt.solution import SolveResult, StartPoint
from ioc_bench.trajopt.step_problem import DEFAULT_INTERVALS, StepRules
from ioc_bench.validation import check_count, check_seed, shown
from ioc_bench.weights import WeightSpec, parse_weights

#: The paper's number of starts.
DEFAULT_STARTS = 15
#: Most starts (and worker processes) one call takes: each start is a full solve.
MAX_STARTS = 10_000
#: Most Hermite-Simpson intervals: the benchmark uses 30; beyond this the NLP will not fit in memory.
MAX_INTERVALS = 10_000


def optimize_gait(
    weights: WeightSpec = "nominal",
    params: GaitParams | None = None,
    task: Task | None = None,
    starts: int = DEFAULT_STARTS,
    seed: int = 0,
    init: Demonstration | None = None,
    guesses: Sequence[Demonstration] = (),
    workers: int | None = None,
    n_intervals: int = DEFAULT_INTERVALS,
    on_start_done: Callable[[int, int], None] | None = None,
    rules: StepRules = StepRules(),
    model: GaitModel = WALKER,
    verify: bool = True,
    features: Sequence[str] | None = None,
) -> Demonstration:
    """Optimize the periodic step for ``weights``; returns the best feasible optimum found.

    Args:
        weights: a name of ``WEIGHT_SETS``, numbers over (hip, knee, dtau) or over all of
            ``features``, or a mapping from feature name to weight. Normalised to unit norm.
        params: the model's parameters (default: the model's nominal ones, ``docs/spec.md``, "Segment parameters").
        task: the task (default: speed 0.27, step length free).
        starts: multi-start size: start 0 is the rough periodic guess, the others perturb
            it with noise drawn from ``seed``. Ignored when ``init`` is given.
        seed: seed of the start perturbations; the same seed gives the same optimum.
        init: warm-start a single solve from this demonstration's primal-dual solution.
        guesses: demonstrations whose trajectories are tried as extra (cold) starts, e.g.
            other weight sets' optima.
        workers: processes for the multi-start (default: all cores).
        n_intervals: Hermite-Simpson intervals.
        on_start_done: called as ``(done, total)`` after each start finishes.
        rules: formulation choices (default: the benchmark's; see ``docs/gait_regime.md``).
        model: the gait model (default: the 5-segment walker).
        verify: check the chosen step for being a local minimum of its own cost, and
            polish it until it is (the check's result is stored in the demonstration).
        features: the basis the cost weighs, in weight order (default: the model's
            :func:`~ioc_bench.features.model_features`; any of its
            :func:`~ioc_bench.features.available_features`, e.g. with ``work`` and
            ``collision``); the demonstration's weights are over it.

    Returns:
        The demonstration, whose ``solver`` reports status, violation, iterations and time
        of the chosen solve and whose ``multistart`` summarises every start. If no start is
        feasible it is still returned, with ``solver.success`` False.

    Raises:
        ValueError: bad input, naming the argument, before any solve: weights; a
            ``params``, ``task``, ``rules``, ``model``, ``init`` or item of ``guesses`` of
            the wrong type; counts below 1 or above :data:`MAX_STARTS` (starts, workers)
            or :data:`MAX_INTERVALS`; a negative seed; a non-callable ``on_start_done``;
            a feature the model lacks.
    """
    model = _instance(model, GaitModel, "model", "ioc_bench.model.walker.WALKER") or WALKER
    params_type = type(model.default_params)
    params = _instance(params, params_type, "params", f"{params_type.__name__}()") or model.default_params
    task = _instance(task, Task, "task", "Task(speed=0.27)") or Task()
    rules = _instance(rules, StepRules, "rules", "StepRules()") or StepRules()
    basis = basis_key(model, features)
    w = parse_weights(weights, basis or model_features(model))
    starts = check_count(starts, "starts", maximum=MAX_STARTS)
    seed = check_seed(seed)
    workers = check_count(workers, "workers", optional=True, maximum=MAX_STARTS)
    n_intervals = check_count(n_intervals, "n_intervals", maximum=MAX_INTERVALS)
    init = _instance(init, Demonstration, "init", "Demonstration.load(path)")
    if isinstance(guesses, (str, bytes, Demonstration)) or not isinstance(guesses, Sequence):
        raise ValueError(f"guesses must be a list of Demonstrations, got {type(guesses).__name__} {shown(guesses)}")
    guesses = [_instance(g, Demonstration, "each of guesses", "Demonstration.load(path)") for g in guesses]
    if on_start_done is not None and not callable(on_start_done):
        raise ValueError(f"on_start_done must be callable, got {shown(on_start_done)}")
    if not isinstance(verify, (bool, np.bool_)):
        raise ValueError(f"verify must be True or False, got {shown(verify)}")
    forward = get_forward_problem(model, n_intervals, basis)
    request = SolveRequest(StartPoint(np.zeros(forward.n_x)), params, task, w, rules=rules)
    if init is not None:
        start = StartPoint(forward.vector(init.trajectory), *_duals(init, forward))
        return _demonstration(forward, forward.solve(replace(request, start=start)), request, None, verify, None)
    origins, points = _start_points(model, params, task, starts, seed, guesses, forward)
    done = [0]

    def progress(_i: int, _r: SolveResult) -> None:
        done[0] += 1
        if on_start_done:
            on_start_done(done[0], len(points))

    results = solve_starts(forward, [replace(request, start=p) for p in points], workers, progress)
    best, summary = pick_best(results, origins)
    return _demonstration(forward, results[best], request, summary, verify, seed)


def _instance(value: object, cls: type, what: str, example: str):
    """``value`` if it is None or a ``cls``; else a ``ValueError`` showing how to make one."""
    if value is not None and not isinstance(value, cls):
        raise ValueError(f"{what} must be a {cls.__name__} (e.g. {example}), got {type(value).__name__} {shown(value)}")
    return value


def _duals(init: Demonstration, forward: ForwardProblem) -> tuple[np.ndarray | None, np.ndarray | None]:
    if init.lam_x.shape == (forward.n_x,) and init.lam_g.shape == (forward.n_g,):
        return init.lam_x, init.lam_g
    return None, None


def _start_points(model, params, task, starts, seed, guesses, forward: ForwardProblem):
    layout = forward.step.layout
    tried = multistart_guesses(model, params, task.speed, task.step_length, forward.n_knots, starts, seed)
    origins = [origin for origin, _ in tried]
    points = [StartPoint(layout.pack(blocks)) for _, blocks in tried]
    for j, demo in enumerate(guesses):
        points.append(StartPoint(forward.vector(demo.trajectory)))
        origins.append(f"guess {j}: weights {_fmt(demo.weight_vector)}")
    return origins, points


def _fmt(w: np.ndarray) -> str:
    return "(" + ", ".join(f"{x:.3g}" for x in w) + ")"


def _demonstration(
    forward: ForwardProblem, result: SolveResult, request: SolveRequest, summary, verify: bool, seed: int | None
) -> Demonstration:
    check = None
    if verify and result.report.success:
        result, check = verify_local_minimum(forward, result, request)
    params, task, w, names = request.params, request.task, request.weights, forward.features
    features = evaluate(result.trajectory, params, names, forward.model)
    return Demonstration(
        trajectory=result.trajectory,
        weights={f: float(x) for f, x in zip(names, w)},
        features=features,
        params=params,
        task=task,
        solver=result.report,
        multistart=summary,
        n_intervals=forward.n_intervals,
        lam_x=result.lam_x,
        lam_g=result.lam_g,
        model=forward.model.name,
        gait=solved_gait_figures(forward, result.x, result.trajectory, params, task, request.rules),
        local_minimum=check,
        seed=seed,
    )
