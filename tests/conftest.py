"""Shared fixtures: demonstrations are slow to make, so each is solved once per session."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest
from hypothesis import settings

from ioc_bench import Demonstration, Task, WalkerParams, optimize_gait

sys.path.insert(0, str(Path(__file__).parent))  # test modules import the made-up results of ``synthetic``
from synthetic import synthetic_result

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
def rolling_feet_demo() -> Demonstration:
    """The nominal-weights step of the rolling-feet model at speed 0.27, best of 3 starts."""
    from ioc_bench.model.feet import ROLLING_FEET

    return optimize_gait("nominal", task=Task(0.27), starts=3, workers=1, model=ROLLING_FEET)


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
    from ioc_bench.synthetic.demos import demonstration
    from ioc_bench.weights import parse_weights

    return demonstration(parse_weights("penalize-knee"))


@pytest.fixture(scope="session")
def ideal_nominal_cached(_isolated_cache) -> Demonstration:
    """The benchmark's nominal demonstration (15 starts), solved once and cached."""
    from ioc_bench.synthetic.demos import demonstration
    from ioc_bench.weights import parse_weights

    return demonstration(parse_weights("nominal"))


@pytest.fixture(scope="session")
def make_result():
    """:func:`synthetic_result`, as a fixture."""
    return synthetic_result
