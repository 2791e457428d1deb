"""Plugins as the command line shows them: refused plugins are never offered, a
name clash is refused with its message; ``run --list`` honours ``--suite`` and ``--json``."""

from __future__ import annotations

import importlib.metadata
import json
import sys
import types

import numpy as np
import pytest

from ioc_bench.cli import main
from ioc_bench.ioc import registry
from ioc_bench.ioc.algorithm import IOCAlgorithm, IOCResult


class _Fixed(IOCAlgorithm):
    description = "returns fixed weights"

    def fit(self, problem):
        return IOCResult(np.ones(problem.n_features))


@pytest.fixture
def plugins(monkeypatch):
    """Installed plugins: one that works, one that fails to import, one not an algorithm, one
    with a name that cannot be a folder, and one named like the built-in ``log-barrier``."""
    monkeypatch.setattr(registry, "_REGISTRY", dict(registry._REGISTRY))
    monkeypatch.setattr(registry, "_CLASH_CHECKED", set())
    registry._load_builtins()
    module = types.ModuleType("fake_ioc_plugins")
    module.Good = type("Good", (_Fixed,), {"description": "a plugin that loads"})
    module.Clash = type("Clash", (_Fixed,), {})
    module.NotAlgorithm = dict
    monkeypatch.setitem(sys.modules, "fake_ioc_plugins", module)
    group = registry.ENTRY_POINT_GROUP
    eps = [
        importlib.metadata.EntryPoint("good-plugin", "fake_ioc_plugins:Good", group),
        importlib.metadata.EntryPoint("broken-plugin", "no_such_module_xyz:Algo", group),
        importlib.metadata.EntryPoint("not-an-algorithm", "fake_ioc_plugins:NotAlgorithm", group),
        importlib.metadata.EntryPoint("../escape", "fake_ioc_plugins:Good", group),
        importlib.metadata.EntryPoint("log-barrier", "fake_ioc_plugins:Clash", group),
    ]
    real = importlib.metadata.entry_points

    def entry_points(**kwargs):
        if kwargs.get("group") == group:
            return importlib.metadata.EntryPoints(eps)
        return real(**kwargs)

    monkeypatch.setattr(importlib.metadata, "entry_points", entry_points)
    return eps


def test_an_unknown_algorithm_lists_only_algorithms_that_load(plugins, capsys):
    with pytest.raises(SystemExit) as exc:
        main(["ioc", "--algorithm", "nope"])
    err = capsys.readouterr().err
    assert exc.value.code == 2 and err.count("\n") == 1, err
    valid = err.split("valid: ")[1].strip().split(", ")
    assert "good-plugin" in valid and valid.count("log-barrier") == 1
    for refused in ("broken-plugin", "not-an-algorithm", "../escape"):
        assert refused not in valid


def test_a_plugin_named_like_a_built_in_is_refused_with_its_message(plugins, capsys):
    assert main(["algorithms", "--json"]) == 0
    report = json.loads(capsys.readouterr().out)
    clash = [m for m in report["skipped_plugins"] if "'log-barrier'" in m]
    assert clash and "name clash refused" in clash[0] and "fake_ioc_plugins:Clash" in clash[0]
    assert report["algorithms"]["log-barrier"] != "returns fixed weights"  # the built-in stays
    registry._CLASH_CHECKED.clear()  # said once per process: as a new process would
    with pytest.warns(registry.PluginWarning, match="name clash refused"):
        cls = registry.get_algorithm("log-barrier")
    assert cls.__module__ == "ioc_bench.ioc.log_barrier"


@pytest.mark.parametrize(
    ("argv", "expect"),
    [
        (["run", "--list", "--suite", "nope", "--json"], "unknown suite 'nope'"),
        (["run", "--list", "--suite", "nope"], "unknown suite 'nope'"),
    ],
)
def test_run_list_refuses_an_unknown_suite(argv, expect, capsys):
    with pytest.raises(SystemExit) as exc:
        main(argv)
    err = capsys.readouterr().err
    assert exc.value.code == 2 and err.count("\n") == 1 and expect in err


def test_run_list_honours_suite_and_json(capsys):
    assert main(["run", "--list", "--json"]) == 0
    every = json.loads(capsys.readouterr().out)["suites"]
    assert {"smoke", "paper"} <= {s["name"] for s in every}
    assert main(["run", "--list", "--suite", "smoke", "--json"]) == 0
    assert [s["name"] for s in json.loads(capsys.readouterr().out)["suites"]] == ["smoke"]
    assert main(["run", "--list", "--suite", "smoke"]) == 0
    assert capsys.readouterr().out.startswith("smoke")
