"""One ``ioc-bench ioc`` case (and one ``run_case``) resolves its model once and builds its
algorithm once, then carries them.

The case is the cheapest there is: inverse KKT (one projection of the observation, no
forward solve) on the cached penalize-knee demonstration, handed over as the cache would;
the transfer and the scoring re-solves, which resolve nothing of the case, are left out.
"""

from __future__ import annotations

import json
import sys
from types import SimpleNamespace

import ioc_bench.synthetic.case as case
from ioc_bench.cli import main
from ioc_bench.features import cost_features
from ioc_bench.ioc.registry import get_algorithm
from ioc_bench.model.catalogue import DEFAULT_MODEL, get_model


def _count_calls(monkeypatch, func, calls: list) -> None:
    """Record every call of ``func``, through every module that holds it (imported by name)
    and through the module that defines it (looked up lazily)."""

    def counted(*args, **kwargs):
        calls.append(args)
        return func(*args, **kwargs)

    for module in list(sys.modules.values()):
        names = [name for name, value in list((getattr(module, "__dict__", None) or {}).items()) if value is func]
        for name in names:
            monkeypatch.setattr(module, name, counted)


def _count_builds(monkeypatch, cls, built: list) -> None:
    """Record every instance of the algorithm class ``cls`` made."""
    init = cls.__init__

    def counted(self, *args, **kwargs):
        built.append(type(self).__name__)
        init(self, *args, **kwargs)

    monkeypatch.setattr(cls, "__init__", counted)


def test_an_ioc_case_resolves_its_model_and_builds_its_algorithm_once(
    penalize_knee_cached, monkeypatch, capsys, tmp_path
):
    monkeypatch.setattr(case, "demonstration", lambda request: penalize_knee_cached)
    monkeypatch.setattr(case.CaseSpec, "transfer_request", lambda self, params=None: None)
    unscored = SimpleNamespace(success=False, status="not scored here", trajectory=None)
    monkeypatch.setattr(case, "regenerate", lambda problem, weights: unscored)
    resolved, built, costed, at_run = [], [], [], []
    _count_calls(monkeypatch, get_model, resolved)
    _count_calls(monkeypatch, cost_features, costed)
    _count_builds(monkeypatch, get_algorithm("inverse-kkt"), built)
    run_spec = case.run_spec

    def marked(*args, **kwargs):  # what was resolved when the case starts running
        at_run.append((len(resolved), len(built), len(costed)))
        return run_spec(*args, **kwargs)

    monkeypatch.setattr(case, "run_spec", marked)
    out = tmp_path / "r.json"
    argv = ["ioc", "--algorithm", "inverse-kkt", "--weights", "penalize-knee", "--out", str(out), "--json"]
    assert main(argv) == 0
    report = json.loads(capsys.readouterr().out)
    assert report["status"] == "converged" and report["weight_error"] < 1e-3, report["reason"]
    assert built == ["InverseKKT"]  # by the command, then handed to run_spec and to the fit
    assert resolved == [(DEFAULT_MODEL,)]  # by the command; the case spec keeps the model object
    # --weights parsed (for any model), checked on the chosen one, and the case's cost
    # features: all before the case runs, none while it does (the spec carries them)
    assert at_run == [(1, 1, 3)] and len(costed) == 3, costed


def test_run_case_resolves_its_model_and_builds_its_algorithm_once(penalize_knee_cached, monkeypatch):
    """The Python API, given the demonstration: the same, with the case's cost features computed once."""
    monkeypatch.setattr(case.CaseSpec, "transfer_request", lambda self, params=None: None)
    unscored = SimpleNamespace(success=False, status="not scored here", trajectory=None)
    monkeypatch.setattr(case, "regenerate", lambda problem, weights: unscored)
    resolved, built, costed = [], [], []
    _count_calls(monkeypatch, get_model, resolved)
    _count_calls(monkeypatch, cost_features, costed)
    _count_builds(monkeypatch, get_algorithm("inverse-kkt"), built)

    result = case.run_case("inverse-kkt", "penalize-knee", "ideal", 0, demo=penalize_knee_cached)
    assert result.status == "converged" and result.weight_error < 1e-3, result.reason
    assert built == ["InverseKKT"] and resolved == [(DEFAULT_MODEL,)] and len(costed) == 1, (built, costed)
