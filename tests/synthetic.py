"""Made-up case results, consistent with their own derived numbers, and made-up demonstrations,
for tests that need no solve."""

from __future__ import annotations

import numpy as np


def estimate_with_error(true, error: float) -> tuple[float, ...]:
    """Unit non-negative weights whose mean absolute difference to the unit ``true`` is ``error``
    (on the way from ``true`` to the simplex vertex farthest from it), so a made-up result is
    consistent with its own weight error."""
    true = np.asarray(true, dtype=float)
    vertex = np.eye(len(true))[int(np.argmin(true))]

    def towards(t: float) -> np.ndarray:
        w = (1 - t) * true + t * vertex
        return w / np.linalg.norm(w)

    def gap(t: float) -> float:
        return float(np.mean(np.abs(towards(t) - true))) - error

    assert 0 <= error <= gap(1.0) + error, f"no unit weights are {error} away from {true}"
    low, high = 0.0, 1.0
    for _ in range(200):
        mid = (low + high) / 2
        low, high = (mid, high) if gap(mid) < 0 else (low, mid)
    return tuple(float(x) for x in towards((low + high) / 2))


def synthetic_result(
    algorithm: str = "log-barrier",
    weight_set: str = "nominal",
    condition: str = "ideal",
    seed: int = 0,
    failed: bool = False,
    config: dict | None = None,
    weight_error: float = 0.01,
    basis: str = "effort",
):
    """A plausible case result without running anything (an estimate ``weight_error`` from the truth)."""
    import math

    from ioc_bench.synthetic.case import CaseResult, CaseSpec

    spec = CaseSpec(algorithm, weight_set, condition, seed, basis=basis)
    features = spec.features
    true = tuple(float(x) for x in spec.true_over_features())
    estimate = estimate_with_error(true, weight_error)
    history = tuple({"weights": list(estimate), "trajectory_error": 1e-4 / (i + 1), "cost_gap": -0.1} for i in range(3))
    return CaseResult(
        algorithm=algorithm,
        weight_set=weight_set,
        condition=condition,
        seed=seed,
        features=features,
        status="failed" if failed else "converged",
        reason="RuntimeError: synthetic failure" if failed else "",
        weights=(math.nan,) * len(features) if failed else estimate,
        true_weights=true,
        weight_error=math.nan if failed else float(np.mean(np.abs(np.array(estimate) - true))),
        trajectory_error=math.nan if failed else 1e-5,
        found_trajectory_error=None if failed else history[2]["trajectory_error"],
        n_solves=3,
        wall_time=1.5,
        history=() if failed else history,
        chosen_iteration=None if failed else 2,
        config=dict(config or {}),
        demo_features={"hip": 1e-3, "knee": 1e-3, "dtau": 1e-4},
        demo_speed=0.27,
        basis=basis,
    )


#: The grid of :func:`grid_errors` (two runs' folders for ``compare``).
ALGORITHMS = ("log-barrier", "bilevel")
CONDITIONS = ("ideal", "noise")
WEIGHT_SETS = ("nominal", "penalize-knee")
SEEDS = (0, 1, 2)


def grid_errors(seed: int = 0) -> dict[tuple, float]:
    """A made-up weight error for every case of a small grid (algorithm, condition, weight set, seed)."""
    rng = np.random.default_rng(seed)
    grid = [(a, c, w, s) for a in ALGORITHMS for c in CONDITIONS for w in WEIGHT_SETS for s in SEEDS]
    return {case: float(rng.uniform(0.01, 0.05)) for case in grid}


def write_run(root, errs: dict[tuple, float], failed=(), configs=None):
    """A results folder holding a case per entry of ``errs`` (failed where listed), as ``run --out`` writes it."""
    from ioc_bench.runner.results import write_result
    from ioc_bench.synthetic.case import CaseSpec

    configs = configs or {}
    for (alg, cond, ws, seed), error in errs.items():
        config = configs.get(alg, {})
        failed_here = (alg, cond, ws, seed) in failed
        result = synthetic_result(alg, ws, cond, seed, failed=failed_here, config=config, weight_error=error)
        write_result(root, CaseSpec(alg, ws, cond, seed, config), result)
    return root


def unsolved_demonstration(model, n_knots: int = 9):
    """A demonstration of ``model`` holding its rough first guess, zero torques and forces and
    no solve: valid as a file (it saves and loads), for what reads a demonstration's model and
    shapes before its step (the refusals of a model without a MuJoCo model)."""
    from ioc_bench.demo import Demonstration
    from ioc_bench.features import cost_features, model_features
    from ioc_bench.task import Task
    from ioc_bench.trajectory import Trajectory
    from ioc_bench.trajopt.initial_guess import rough_step
    from ioc_bench.trajopt.solution import SolverReport

    params, task = model.default_params, Task(0.27)
    link = model.linkage(params)
    blocks = rough_step(model, params, task.speed, n_knots)
    n_seg, n_pin, n_lock = len(link.segments), len(link.pins), len(link.locked)
    trajectory = Trajectory(
        blocks["dt"][0],
        blocks["q"],
        blocks["v"],
        np.zeros((n_knots, len(link.actuated))),
        acc=np.zeros((n_knots, n_seg, 3)),
        lock=np.zeros((n_knots, n_lock)),
        pin_forces=np.zeros((n_knots, n_pin, 2)),
        impulses=np.zeros((n_pin, 2)),
        trail_impulse=np.zeros(2),
        lock_impulses=np.zeros(n_lock),
    )
    cost = cost_features(model)
    weights = dict.fromkeys(cost, 1.0 / np.sqrt(len(cost)))
    features = dict.fromkeys(model_features(model), 0.0)
    report = SolverReport("Solve_Succeeded", True, 0.0, 0.0, 1, 0.1, 1.0)
    return Demonstration(
        trajectory, weights, features, params, task, report, n_intervals=(n_knots - 1) // 2, model=model.name
    )
