"""Shared fixtures: demonstrations are slow to make, so each is solved once per session."""

from __future__ import annotations

import numpy as np
import pytest

from ioc_bench import Demonstration, Task, WalkerParams, optimize_gait


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
def ideal_nominal_cached(_isolated_cache) -> Demonstration:
    """The benchmark's nominal demonstration (15 starts), solved once and cached."""
    from ioc_bench.bench.demos import demonstration
    from ioc_bench.weights import parse_weights

    return demonstration(parse_weights("nominal"))
