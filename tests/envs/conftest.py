"""Replay results shared by the env tests: each MuJoCo walk runs once per session."""

from __future__ import annotations

import pytest

from ioc_bench import Demonstration


@pytest.fixture(scope="session")
def nominal_closed_loop(nominal_demo: Demonstration):
    """The nominal demonstration walked 10 steps by the closed-loop check (about 2 s)."""
    from envs.checks import closed_loop_replay

    return closed_loop_replay(nominal_demo, steps=10)


@pytest.fixture(scope="session")
def nominal_open_loop(nominal_demo: Demonstration):
    from envs.checks import open_loop_replay

    return open_loop_replay(nominal_demo)
