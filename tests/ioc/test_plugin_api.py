"""The plugin API holds across releases, and whatever a plugin returns is checked at the boundary.

The plugins in ``plugin_pkg/`` are written to API 1, 2, 3 and 4 and installed here as a package
(its files and a ``.dist-info`` with the entry points, which is what ``pip install`` leaves),
then run through each entry point: ``run_case``, ``ioc-bench ioc`` and the suite runner.
"""

from __future__ import annotations

import importlib
import json
import os
import shutil
import subprocess
import sys
import tomllib
import warnings
from pathlib import Path

import numpy as np
import pytest

import ioc_bench
from ioc_bench import IOCResult, IterationRecord, ModelFit, WeightRegion, run_case
from ioc_bench.ioc import registry
from ioc_bench.ioc.contract import contract_breach
from ioc_bench.runner.results import load_results
from ioc_bench.runner.run import run_cases
from ioc_bench.synthetic.case import CaseSpec

PACKAGE = Path(__file__).parent / "plugin_pkg"
MALFORMED = [
    "fields-in-wrong-order",
    "dict-record",
    "string-error",
    "string-weights",
    "record-weights-wrong-size",
    "chosen-out-of-range",
    "notes-not-json",
    "status-not-text",
    "region-inverted",
    "region-wrong-size",
    "nan-weights",
    "not-a-result",
    "fit-not-a-model-fit",
    "fit-nan-statistic",
    "fit-rejected-not-bool",
]


@pytest.fixture(scope="module")
def site(tmp_path_factory) -> Path:
    """The test plugins installed into a fresh site directory on ``sys.path``."""
    site = tmp_path_factory.mktemp("site")
    shutil.copytree(PACKAGE / "iocbench_test_plugins", site / "iocbench_test_plugins")
    info = site / "iocbench_test_plugins-0.1.0.dist-info"
    info.mkdir()
    (info / "METADATA").write_text("Metadata-Version: 2.1\nName: iocbench-test-plugins\nVersion: 0.1.0\n")
    project = tomllib.loads(PACKAGE.joinpath("pyproject.toml").read_text())["project"]
    lines = [f"{name} = {target}" for name, target in project["entry-points"]["ioc_bench.algorithms"].items()]
    (info / "entry_points.txt").write_text("[ioc_bench.algorithms]\n" + "\n".join(lines) + "\n")
    registered, checked = dict(registry._REGISTRY), set(registry._CLASH_CHECKED)
    sys.path.insert(0, str(site))
    importlib.invalidate_caches()
    yield site
    sys.path.remove(str(site))
    importlib.invalidate_caches()
    # the plugins it registered leave with it: later tests see the built-ins only
    registry._REGISTRY.clear()
    registry._REGISTRY.update(registered)
    registry._CLASH_CHECKED.clear()
    registry._CLASH_CHECKED.update(checked)
    for module in [m for m in sys.modules if m.split(".")[0] == "iocbench_test_plugins"]:
        del sys.modules[module]


@pytest.fixture(scope="module")
def demo(penalize_knee_cached):
    return penalize_knee_cached


def test_api1_record_keeps_its_meaning_and_warns():
    with pytest.warns(DeprecationWarning, match="API 1"):
        record = IterationRecord((0.6, 0.8), 0.25, "Solve_Succeeded", -0.1)
    assert record.trajectory_error == 0.25 and np.isnan(record.tracking_error)
    assert record.solve_status == "Solve_Succeeded" and record.extra == {"cost_gap": -0.1}
    with pytest.warns(DeprecationWarning):
        assert IterationRecord((1.0,), 0.5).trajectory_error == 0.5  # two arguments: API 1 too


def test_api2_and_keyword_records_need_no_warning():
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        positional = IterationRecord((0.6, 0.8), 0.01, 0.25, "Solve_Succeeded", {"k": 1})
        keywords = IterationRecord(
            (0.6, 0.8), tracking_error=0.01, trajectory_error=0.25, solve_status="Solve_Succeeded"
        )
    assert positional.tracking_error == keywords.tracking_error == 0.01
    assert positional.trajectory_error == keywords.trajectory_error == 0.25
    with pytest.raises(TypeError, match="both by position and by keyword"):
        IterationRecord((1.0,), 0.1, 0.2, tracking_error=0.3)


def test_the_api_version_is_published():
    assert ioc_bench.API_VERSION == 4


@pytest.mark.parametrize("kind", MALFORMED)
def test_the_contract_catches_each_malformed_answer(kind):
    """The boundary check alone, on answers built like the malformed plugin's (no solves)."""
    w = np.array([0.6, 0.8])
    good = IterationRecord(tuple(w), tracking_error=0.1, trajectory_error=0.2, solve_status="Solve_Succeeded")
    answers = {
        "fields-in-wrong-order": IOCResult(w, history=(IterationRecord(tuple(w), "Solve_Succeeded", 0.1, 0.2),)),
        "dict-record": IOCResult(w, history=(good.to_dict(),)),
        "string-error": IOCResult(w, history=(IterationRecord(tuple(w), tracking_error="0.1"),)),
        "string-weights": IOCResult(np.array(["0.6", "0.8"])),
        "record-weights-wrong-size": IOCResult(w, history=(IterationRecord((1.0,), tracking_error=0.1),)),
        "chosen-out-of-range": IOCResult(w, history=(good,), chosen_iteration=5),
        "notes-not-json": IOCResult(w, notes={"x": object()}),
        "status-not-text": IOCResult(w, status=3),
        "region-inverted": IOCResult(w, uncertainty=WeightRegion(tuple(w + 0.1), tuple(w - 0.1))),
        "region-wrong-size": IOCResult(w, uncertainty=WeightRegion((0.0,), (1.0,))),
        "nan-weights": IOCResult(np.full(2, np.nan)),
        "not-a-result": {"weights": w},
        "fit-not-a-model-fit": IOCResult(w, model_fit={"rejected": False}),
        "fit-nan-statistic": IOCResult(w, model_fit=ModelFit(False, float("nan"), 2.0, 0.05, 0.0025)),
        "fit-rejected-not-bool": IOCResult(w, model_fit=ModelFit("no", 1.0, 2.0, 0.05, 0.0025)),
    }
    assert contract_breach(IOCResult(w, history=(good,), chosen_iteration=0), 2) == ""
    assert contract_breach(IOCResult(w, model_fit=ModelFit(False, 1.0, 2.0, 0.05, 0.0025)), 2) == ""
    reason = contract_breach(answers[kind], 2)
    assert reason and "\n" not in reason


def test_plugins_of_every_api_version_run_through_run_case(site, demo):
    for name in ("api1-coordinate-search", "api2-two-candidates", "api3-with-region"):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", DeprecationWarning)
            result = run_case(name, "penalize-knee", "ideal", 0, demo=demo)
        assert not result.failed, (name, result.reason)
        chosen = result.history[result.chosen_iteration]
        assert isinstance(chosen["trajectory_error"], float) and isinstance(chosen["solve_status"], str)
        assert result.found_trajectory_error == pytest.approx(chosen["trajectory_error"])
        assert result.n_solves >= 2
    region = run_case("api3-with-region", "penalize-knee", "ideal", 0, demo=demo).uncertainty
    assert region["lower"] == [0.0, 0.0, 0.0] or tuple(region["lower"]) == (0.0, 0.0, 0.0)


def test_an_api4_plugin_reports_its_model_fit_and_older_ones_report_none(site, demo):
    """The misfit test travels to the record (the region then conditional on it); a plugin
    written before it existed runs unchanged and reports no test."""
    result = run_case("api4-with-model-fit", "penalize-knee", "ideal", 0, demo=demo)
    assert not result.failed, result.reason
    assert result.misfit is True and result.model_fit["method"] == "rejects every model"
    assert result.covered is True  # the region still holds the truth; it is conditional on a rejected model
    older = run_case("api3-with-region", "penalize-knee", "ideal", 0, demo=demo)
    assert older.model_fit is None and older.misfit is None


@pytest.mark.parametrize("kind", ["fields-in-wrong-order", "dict-record", "string-weights", "notes-not-json"])
def test_malformed_plugin_output_is_a_failed_case_with_its_cost(site, demo, kind):
    result = run_case("malformed", "penalize-knee", "ideal", 0, config={"kind": kind}, demo=demo)
    assert result.failed and result.reason and "\n" not in result.reason
    assert result.n_solves >= 2 and result.wall_time > 0  # the projection and its one solve were spent
    json.dumps(result.to_dict())  # nothing unserialisable reached the record


def test_the_runner_records_a_malformed_plugin_case_with_its_time_and_solves(site, demo, tmp_path):
    specs = [CaseSpec("malformed", "penalize-knee", "ideal", 0, {"kind": k}) for k in ("dict-record", "nan-weights")]
    summary = run_cases(specs, tmp_path, workers=1)
    assert summary.failed == 2
    for result in load_results(tmp_path):
        assert result.failed and result.n_solves >= 2 and result.wall_time > 0, result


def test_ioc_bench_ioc_runs_an_api1_plugin_and_records_a_malformed_one(site, demo, tmp_path):
    env = dict(os.environ, PYTHONPATH=os.pathsep.join([str(site), os.environ.get("PYTHONPATH", "")]))
    command = [sys.executable, "-m", "ioc_bench.cli", "ioc", "--weights", "penalize-knee", "--json"]
    ok = subprocess.run(
        [*command, "--algorithm", "api1-coordinate-search", "--out", str(tmp_path / "a.json")],
        capture_output=True,
        text=True,
        env=env,
        timeout=600,
    )
    assert ok.returncode == 0, ok.stderr
    assert "Traceback" not in ok.stderr and json.loads(ok.stdout)["status"] == "converged"
    bad = subprocess.run(
        [
            *command,
            "--algorithm",
            "malformed",
            "--config",
            '{"kind": "string-error"}',
            "--out",
            str(tmp_path / "b.json"),
        ],
        capture_output=True,
        text=True,
        env=env,
        timeout=600,
    )
    assert bad.returncode == 1 and "Traceback" not in bad.stderr
    record = json.loads((tmp_path / "b.json").read_text())
    assert record["status"] == "failed" and "tracking_error" in record["reason"] and record["n_solves"] >= 2
