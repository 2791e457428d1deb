"""Fixtures the human-track tests share."""

import pytest

from ioc_bench.ioc.registry import get_algorithm


@pytest.fixture
def one_trial_algorithm(monkeypatch) -> str:
    """A built-in marked as taking one trial only (every built-in takes several), so a case
    with two training speeds fails at once, before any solve; returns its name."""
    monkeypatch.setattr(get_algorithm("inverse-kkt"), "multi_trial", False)
    return "inverse-kkt"
