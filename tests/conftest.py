"""Shared fixtures: demonstrations are slow to make, so each is solved once per session."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import settings

from ioc_bench import Demonstration, Task, WalkerParams, optimize_gait

# Property-based tests draw their examples from a fixed seed: the same examples every run.
settings.register_profile("ioc-bench", derandomize=True, deadline=None, database=None, print_blob=True)
settings.load_profile("ioc-bench")


@pytest.fixture
def rng() -> np.random.Generator:
    return np.random.default_rng(0)


@pytest.fixture(scope="session")
def nominal_demo() -> Demonstration:
    """The nominal-weights step at speed 0.27 from the single default start (a few seconds)."""
    demo = optimize_gait("nominal", task=Task(0.27), starts=1, seed=0, workers=1)
    assert demo.solver.success, demo.solver
    return demo


@pytest.fixture(scope="session")
def heavy_legs_demo() -> Demonstration:
    """The nominal-weights step of a walker with 10 % heavier legs (the "mass" variant)."""
    demo = optimize_gait("nominal", params=WalkerParams().with_leg_mass_scale(1.1), starts=1, seed=0, workers=1)
    assert demo.solver.success, demo.solver
    return demo


@pytest.fixture(scope="session", autouse=True)
def _isolated_cache(tmp_path_factory):
    """Demonstrations are cached per test session, never in the user's cache."""
    import os

    path = tmp_path_factory.mktemp("ioc-bench-cache")
    old = os.environ.get("IOC_BENCH_CACHE")
    os.environ["IOC_BENCH_CACHE"] = str(path)
    yield path
    if old is None:
        os.environ.pop("IOC_BENCH_CACHE", None)
    else:
        os.environ["IOC_BENCH_CACHE"] = old


@pytest.fixture(scope="session")
def penalize_knee_cached(_isolated_cache) -> Demonstration:
    """The benchmark's penalize-knee demonstration at speed 0.27 (seed 0), solved once and cached."""
    from ioc_bench.bench.demos import demonstration
    from ioc_bench.weights import parse_weights

    return demonstration(parse_weights("penalize-knee"))


@pytest.fixture(scope="session")
def ideal_nominal_cached(_isolated_cache) -> Demonstration:
    """The benchmark's nominal demonstration (15 starts), solved once and cached."""
    from ioc_bench.bench.demos import demonstration
    from ioc_bench.weights import parse_weights

    return demonstration(parse_weights("nominal"))


def synthetic_result(
    algorithm: str = "log-barrier",
    weight_set: str = "nominal",
    condition: str = "ideal",
    seed: int = 0,
    failed: bool = False,
    config: dict | None = None,
    weight_error: float = 0.01,
):
    """A plausible case result without running anything (true weights as the estimate)."""
    import math

    from ioc_bench.bench.case import CaseResult
    from ioc_bench.bench.conditions import get_condition
    from ioc_bench.weights import parse_weights

    features = get_condition(condition).features
    true = tuple(float(x) for x in parse_weights(weight_set, features))
    history = tuple({"weights": list(true), "trajectory_error": 1e-4 / (i + 1), "cost_gap": -0.1} for i in range(3))
    return CaseResult(
        algorithm=algorithm,
        weight_set=weight_set,
        condition=condition,
        seed=seed,
        features=features,
        status="failed" if failed else "converged",
        reason="RuntimeError: synthetic failure" if failed else "",
        weights=(math.nan,) * len(features) if failed else true,
        true_weights=true,
        weight_error=math.nan if failed else weight_error,
        trajectory_error=math.nan if failed else 1e-5,
        n_solves=3,
        wall_time=1.5,
        history=() if failed else history,
        chosen_iteration=None if failed else 2,
        config=dict(config or {}),
        demo_features={"hip": 1e-3, "knee": 1e-3, "dtau": 1e-4},
        demo_speed=0.27,
    )


@pytest.fixture(scope="session")
def make_result():
    """:func:`synthetic_result`, as a fixture."""
    return synthetic_result
