"""The algorithm registry: decorator, entry-point plugins, clashes and broken plugins."""

from __future__ import annotations

import importlib.metadata
import sys
import types

import numpy as np
import pytest

import ioc_bench
from ioc_bench.ioc import registry
from ioc_bench.ioc.algorithm import IOCAlgorithm, IOCResult


class _Fixed(IOCAlgorithm):
    description = "returns fixed weights"

    def fit(self, problem):
        return IOCResult(np.ones(problem.n_features))


@pytest.fixture
def clean_registry(monkeypatch):
    """Work on a copy of the registry so tests cannot leak registrations."""
    monkeypatch.setattr(registry, "_REGISTRY", dict(registry._REGISTRY))
    registry._load_builtins()
    return registry._REGISTRY


def _fake_entry_points(monkeypatch, eps: list[importlib.metadata.EntryPoint]) -> None:
    real = importlib.metadata.entry_points

    def entry_points(**kwargs):
        if kwargs.get("group") == registry.ENTRY_POINT_GROUP:
            return importlib.metadata.EntryPoints(eps)
        return real(**kwargs)

    monkeypatch.setattr(importlib.metadata, "entry_points", entry_points)


def test_builtins_are_listed():
    names = ioc_bench.algorithms()
    assert "log-barrier" in names and "analytic-center" in names


def test_decorator_registers_and_clash_is_refused(clean_registry):
    ioc_bench.register_algorithm("fixed-test")(type("FixedA", (_Fixed,), {}))
    assert "fixed-test" in ioc_bench.algorithms()
    with pytest.raises(registry.AlgorithmError, match="already registered"):
        ioc_bench.register_algorithm("fixed-test")(type("FixedB", (_Fixed,), {}))
    with pytest.raises(registry.AlgorithmError, match="not an IOCAlgorithm"):
        ioc_bench.register_algorithm("not-an-algorithm")(dict)


def test_unknown_algorithm_lists_valid_names(clean_registry):
    with pytest.raises(registry.AlgorithmError, match=r"valid: .*log-barrier"):
        ioc_bench.make_algorithm("no-such-algorithm")


def test_bad_config_field_is_reported(clean_registry):
    with pytest.raises(registry.AlgorithmError, match="bad config"):
        ioc_bench.make_algorithm("log-barrier", no_such_field=1)


def test_entry_point_plugin_appears_without_import(clean_registry, monkeypatch):
    module = types.ModuleType("fake_ioc_plugin")
    module.Plugin = type("Plugin", (_Fixed,), {"description": "a third-party plugin"})
    monkeypatch.setitem(sys.modules, "fake_ioc_plugin", module)
    ep = importlib.metadata.EntryPoint("third-party", "fake_ioc_plugin:Plugin", registry.ENTRY_POINT_GROUP)
    _fake_entry_points(monkeypatch, [ep])
    assert "third-party" in ioc_bench.algorithms()
    assert "third-party" not in clean_registry  # listed, not loaded yet
    algo = ioc_bench.make_algorithm("third-party")
    assert isinstance(algo, module.Plugin)
    assert registry.describe_algorithms()["third-party"] == "a third-party plugin"


def test_broken_plugin_is_reported_by_name_and_skipped(clean_registry, monkeypatch):
    bad = importlib.metadata.EntryPoint("broken", "no_such_module_xyz:Algo", registry.ENTRY_POINT_GROUP)
    clash = importlib.metadata.EntryPoint("log-barrier", "fake_clash:Algo", registry.ENTRY_POINT_GROUP)
    module = types.ModuleType("fake_clash")
    module.Algo = type("Algo", (_Fixed,), {})
    monkeypatch.setitem(sys.modules, "fake_clash", module)
    _fake_entry_points(monkeypatch, [bad, clash])
    with pytest.warns(registry.PluginWarning, match="'broken'.*failed to import"):
        described = registry.describe_algorithms()
    assert "broken" not in described and "log-barrier" in described
    with pytest.warns(registry.PluginWarning, match="'broken'"), pytest.raises(registry.AlgorithmError):
        ioc_bench.make_algorithm("broken")
    assert registry.get_algorithm("log-barrier").__module__ == "ioc_bench.ioc.log_barrier"


def test_builtins_survive_their_module_being_imported_elsewhere(monkeypatch):
    """A built-in whose import registered it in another registry copy (e.g. during a test)
    is still registered by name in the real one."""
    registry._load_builtins()
    without = {k: v for k, v in registry._REGISTRY.items() if k != "analytic-center"}
    monkeypatch.setattr(registry, "_REGISTRY", without)
    assert "analytic-center" in ioc_bench.algorithms()


@pytest.mark.parametrize(
    ("config", "message"),
    [
        ({"n_random": -1}, "n_random must be >= 0"),
        ({"forward_start": "nope"}, "forward_start must be 'warm' or 'cold'"),
        ({"nope": 1}, r"unknown field\(s\) nope; fields: n_random"),
        ({"n_random": 1.5}, "n_random must be an integer, got 1.5"),
        ({"n_random": True}, "n_random must be an integer, got True"),
        ({"forward_start": 3}, "forward_start must be a string"),
        ({"perturbation": float("nan")}, "perturbation must be a finite number"),
    ],
)
def test_configs_are_checked_against_their_types_and_rules(config, message):
    with pytest.raises(registry.AlgorithmError, match=message) as exc:
        ioc_bench.make_algorithm("log-barrier", **config)
    assert "\n" not in str(exc.value)


def test_json_forms_are_accepted_and_converted():
    algo = ioc_bench.make_algorithm("analytic-center", proximal=[1, 2], perturbation=1)
    assert algo.config.proximal == (1.0, 2.0) and isinstance(algo.config.perturbation, float)
    with pytest.raises(registry.AlgorithmError, match="proximal must be a list of finite numbers"):
        ioc_bench.make_algorithm("analytic-center", proximal=[1, "x"])


def test_canonical_config_keeps_only_what_differs_from_the_defaults():
    assert registry.canonical_config("analytic-center", {"n_random": 0, "proximal": [30, 300.0]}) == {}
    assert registry.canonical_config("log-barrier", {"offset": 1.5, "n_random": 2}) == {"n_random": 2}
    assert registry.canonical_config("log-barrier", None) == {}
    with pytest.raises(registry.AlgorithmError, match="must be a mapping"):
        registry.canonical_config("log-barrier", [1, 2])


@pytest.mark.parametrize("config", [{}, {"offset": 1.5, "n_random": 2}])
def test_canonical_config_builds_no_algorithm(monkeypatch, config):
    """A case builds its algorithm once, to run it; making its canonical config builds none."""
    expected = ioc_bench.make_algorithm("log-barrier", **config).config_dict()
    built = []
    make = registry.make_algorithm
    monkeypatch.setattr(registry, "make_algorithm", lambda *a, **k: built.append(a) or make(*a, **k))
    assert registry.canonical_config("log-barrier", config) == {k: v for k, v in config.items() if k == "n_random"}
    assert registry._effective_config("log-barrier", config) == expected
    assert not built
    with pytest.raises(registry.AlgorithmError, match=r"n_random must be an integer, got 1\.5"):
        registry.canonical_config("log-barrier", {"n_random": 1.5})
    with pytest.raises(registry.AlgorithmError, match="n_random must be >= 0"):
        registry.canonical_config("log-barrier", {"n_random": -1})


def test_an_algorithm_that_builds_its_own_way_is_built_to_ask_its_config(clean_registry):
    class OwnWay(_Fixed):
        def __init__(self, **overrides):
            super().__init__(**overrides)
            self.built = True

        def config_dict(self):
            return {"marker": 1}

    ioc_bench.register_algorithm("own-way")(OwnWay)
    assert registry.canonical_config("own-way", {}) == {}
    assert registry._effective_config("own-way", {}) == {"marker": 1}


@pytest.mark.parametrize("name", ["../x", "a/b", ".hidden", "", "x" * 101, "a b", "..", "a..b"])
def test_names_that_cannot_be_folder_names_are_refused(clean_registry, name):
    with pytest.raises(registry.AlgorithmError, match="invalid algorithm name"):
        ioc_bench.register_algorithm(name)(type("Named", (_Fixed,), {}))
