"""The worked plugin example (docs/plugin_api.md) registers, runs and is scored like a built-in."""

from __future__ import annotations

import importlib.util
from pathlib import Path

import numpy as np

import ioc_bench

EXAMPLE = Path(__file__).resolve().parents[1] / "examples" / "custom_algorithm.py"


def test_custom_algorithm_example(ideal_nominal_cached, monkeypatch):
    from ioc_bench.ioc import registry

    monkeypatch.setattr(registry, "_REGISTRY", dict(registry._REGISTRY))
    spec = importlib.util.spec_from_file_location("custom_algorithm_example", EXAMPLE)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    assert "random-search" in ioc_bench.algorithms()
    result = ioc_bench.run_case("random-search", "nominal", "ideal", seed=0, config={"candidates": 2})
    # the candidates' solves start at the projected observation: one projection, then a solve each
    assert result.status == "max_iterations" and result.n_solves == 1 + 2
    assert np.isfinite(result.weight_error) and len(result.history) == 2
    assert sum(1 for line in EXAMPLE.read_text().splitlines() if line.strip()) < 45


GRADIENT_EXAMPLE = EXAMPLE.parent / "gradient_algorithm.py"


def test_gradient_algorithm_example_descends(penalize_knee_cached, monkeypatch):
    """The gradient-based plugin uses only the public differentiable view, and its steps lower
    the tracking error of the weights' optimum."""
    from ioc_bench.ioc import registry

    monkeypatch.setattr(registry, "_REGISTRY", dict(registry._REGISTRY))
    spec = importlib.util.spec_from_file_location("gradient_algorithm_example", GRADIENT_EXAMPLE)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    result = ioc_bench.run_case("tracking-gradient", "penalize-knee", "ideal", seed=0, config={"iterations": 3})
    errors = [h["tracking_error"] for h in result.history]
    assert len(errors) == 3 and errors[-1] < errors[0], (result.status, result.reason)
    assert result.oracle["calls"]["sensitivity"] == 3
    assert "._" not in GRADIENT_EXAMPLE.read_text().replace("__", "")  # no private access
    assert sum(1 for line in GRADIENT_EXAMPLE.read_text().splitlines() if line.strip()) < 60


TRACKING_EXAMPLE = EXAMPLE.parent / "track_demonstration.py"


def test_track_demonstration_example(nominal_demo, tmp_path, capsys):
    """Four walkers of different leg masses track the demonstration in a vector env (3 steps here)."""
    from PIL import Image

    spec = importlib.util.spec_from_file_location("track_demonstration_example", TRACKING_EXAMPLE)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    result = module.main(nominal_demo, out=str(tmp_path / "walk.gif"), steps=3)
    assert result["fell"] == [False] * 4
    assert result["out_of_time"] == [False] * 4
    assert all(0 < rms < 0.05 for rms in result["rms"])  # rad (measured 1e-3..1e-2 over 10 steps)
    with Image.open(result["gif"]) as gif:
        assert gif.n_frames > 20 and gif.size == (480, 360)
    out = capsys.readouterr().out
    assert out.count("3 steps, tracking error RMS") == 4


REGION_EXAMPLE = EXAMPLE.parent / "region_algorithm.py"


def test_region_example_reports_a_checked_region(penalize_knee_cached, monkeypatch):
    """The bootstrap plugin's region passes the contract and is recorded with the case."""
    from ioc_bench.ioc import registry

    monkeypatch.setattr(registry, "_REGISTRY", dict(registry._REGISTRY))
    spec = importlib.util.spec_from_file_location("region_algorithm_example", REGION_EXAMPLE)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    result = ioc_bench.run_case("bootstrap-kkt", "penalize-knee", "ideal", seed=0, config={"resamples": 3})
    assert not result.failed, result.reason
    region = result.uncertainty
    assert region["method"].startswith("parametric bootstrap") and result.covered is not None
    assert all(lo <= w <= hi for lo, w, hi in zip(region["lower"], result.weights, region["upper"]))
