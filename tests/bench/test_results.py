"""Result files: a case's identity (with its canonical config), the one-error reader, the directory."""

from __future__ import annotations

import contextlib
import dataclasses
import json
import math
import os
from pathlib import Path

import pytest
from hypothesis import given
from hypothesis import strategies as st

from ioc_bench.ioc.registry import AlgorithmError
from ioc_bench.provenance import provenance
from ioc_bench.runner.leaderboard import markdown
from ioc_bench.runner.results import (
    ResultFileError,
    load_results,
    read_result,
    result_files,
    results_directory,
    stored_result,
    write_result,
)
from ioc_bench.synthetic.board import summarise
from ioc_bench.synthetic.case import CaseResult, CaseSpec
from ioc_bench.synthetic.results import parse_result, recorded_spec

# -- identity ------------------------------------------------------------------------------


def test_a_config_spelling_out_defaults_is_the_same_case():
    plain = CaseSpec("analytic-center", "nominal", "ideal", 0)
    spelled = CaseSpec("analytic-center", "nominal", "ideal", 0, {"n_random": 0, "proximal": [30, 300]})
    assert spelled.config == {} and spelled.key == plain.key == "analytic-center/nominal__ideal__seed0"


def test_configs_with_the_same_effect_share_a_key_and_different_ones_do_not():
    a = CaseSpec("log-barrier", "nominal", "ideal", 0, {"n_random": 1, "perturbation": 1})
    b = CaseSpec("log-barrier", "nominal", "ideal", 0, {"perturbation": 1.0, "n_random": 1, "offset": 1.5})
    c = CaseSpec("log-barrier", "nominal", "ideal", 0, {"n_random": 2})
    assert a.key == b.key != c.key and a.config == {"n_random": 1, "perturbation": 1.0}
    assert a.key.startswith("log-barrier/nominal__ideal__seed0__cfg")


@pytest.mark.parametrize(
    ("fields", "message"),
    [
        (("../x", "nominal", "ideal", 0), "invalid algorithm name"),
        (("a/b", "nominal", "ideal", 0), "invalid algorithm name"),
        (("log-barrier", "nominal", "ideal", -1), "non-negative integer"),
        (("log-barrier", "nominal", "ideal", True), "non-negative integer"),
        (("log-barrier", "nope", "ideal", 0), "unknown weight set"),
        (("log-barrier", "nominal", "nope", 0), "unknown condition"),
        (("log-barrier", "nominal", "ideal", 0, {"nope": 1}), "unknown field"),
        (("log-barrier", "nominal", "ideal", 0, [1, 2]), "must be a mapping"),
        (("no-such-algo", "nominal", "ideal", 0, {"n_random": 1}), "unknown algorithm"),
    ],
)
def test_a_bad_case_is_refused_when_made(fields, message):
    with pytest.raises(ValueError, match=message):
        CaseSpec(*fields)


# -- the reader: one error type --------------------------------------------------------------


def test_round_trip_through_a_file(tmp_path, make_result):
    result = make_result(config={"n_random": 1})
    spec = CaseSpec("log-barrier", "nominal", "ideal", 0, {"n_random": 1})
    path = write_result(tmp_path, spec, result)
    assert read_result(path) == result and load_results(tmp_path) == [result]


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("null", "expected a JSON object, got null"),
        ("[1, 2]", "expected a JSON object, got list"),
        ("{not json", "not JSON"),
        ("", "not JSON"),
    ],
)
def test_malformed_files_raise_result_file_error_naming_the_file(tmp_path, text, message):
    path = tmp_path / "x.json"
    path.write_text(text)
    with pytest.raises(ResultFileError, match=message) as exc:
        read_result(path)
    assert str(path) in str(exc.value) and "\n" not in str(exc.value)


@pytest.mark.parametrize(
    ("change", "message"),
    [
        ({"wall_time": "fast"}, "wall_time must be a number"),
        ({"seed": "0"}, "seed must be an integer"),
        ({"seed": -3}, "seed must be a non-negative integer"),
        ({"weights": [0.5, 0.5]}, "weights has 2 entries for 3 features"),
        ({"features": "hip"}, "features must be a list of strings"),
        ({"history": [1, 2]}, "history must be a list of objects"),
        ({"surprise": 1}, "unknown field"),
        ({"n_solves": True}, "n_solves must be an integer"),
    ],
)
def test_wrongly_typed_fields_are_named(tmp_path, change, message, make_result):
    data = make_result().to_dict() | change
    path = tmp_path / "x.json"
    path.write_text(json.dumps(data))
    with pytest.raises(ResultFileError, match=message):
        read_result(path)


def test_missing_fields_are_named(make_result):
    data = make_result().to_dict()
    del data["status"], data["seed"]
    with pytest.raises(ValueError, match=r"missing field\(s\) seed, status"):
        parse_result(data)


_json = st.recursive(
    st.none() | st.booleans() | st.integers() | st.floats() | st.text(max_size=8),
    lambda inner: st.lists(inner, max_size=4) | st.dictionaries(st.text(max_size=8), inner, max_size=4),
    max_leaves=12,
)
_FIELDS = [f.name for f in dataclasses.fields(CaseResult)]


@given(data=_json)
def test_property_any_json_value_is_a_result_or_a_value_error(data):
    try:
        result = parse_result(data)
    except ValueError:
        return
    assert isinstance(result, CaseResult)  # pragma: no cover - random JSON is never a result


@given(
    failed=st.booleans(),
    field=st.sampled_from([*_FIELDS, "extra"]),
    value=_json,
    drop=st.booleans(),
)
def test_property_one_field_changed_reads_or_raises_and_summarises(make_result, failed, field, value, drop):
    """Reading gives a ``CaseResult`` or ``ValueError``; what reads back, the leaderboard can show."""
    data = make_result(failed=failed).to_dict()
    if drop:
        data.pop(field, None)
    else:
        data[field] = value
    try:
        result = parse_result(json.loads(json.dumps(data)))
    except ValueError:
        return
    assert isinstance(result, CaseResult)
    assert len(result.weights) == len(result.features) == len(result.true_weights)
    summarise([result])
    markdown([result])


@given(raw=st.binary(max_size=200))
def test_property_any_bytes_read_as_a_result_or_result_file_error(tmp_path_factory, raw):
    path = tmp_path_factory.mktemp("raw") / "nominal__ideal__seed0.json"
    path.write_bytes(raw)
    with contextlib.suppress(ResultFileError):  # anything else fails the test
        read_result(path)


# -- the directory ---------------------------------------------------------------------------


def test_only_files_named_like_results_are_read(tmp_path, make_result):
    spec = CaseSpec("log-barrier", "nominal", "ideal", 0)
    write_result(tmp_path, spec, make_result())
    (tmp_path / "board").mkdir()
    (tmp_path / "board" / "leaderboard.json").write_text("{}")  # a leaderboard written into the results
    (tmp_path / "log-barrier" / "notes.json").write_text("[]")
    (tmp_path / "log-barrier" / ".nominal__ideal__seed0.json.abc123.tmp").write_text("{")  # a killed writer
    (tmp_path / "top.json").write_text("null")
    assert [p.name for p in result_files(tmp_path)] == ["nominal__ideal__seed0.json"]
    assert len(load_results(tmp_path)) == 1


def test_missing_directory_is_a_result_file_error(tmp_path):
    with pytest.raises(ResultFileError, match="not found"):
        load_results(tmp_path / "nope")


def test_holding_a_directory_locks_it_and_removes_temporaries(tmp_path):
    (tmp_path / "log-barrier").mkdir()
    temporary = tmp_path / "log-barrier" / ".nominal__ideal__seed0.json.abc123.tmp"
    temporary.write_text("{")
    with results_directory(tmp_path):
        assert not temporary.exists()
        with pytest.raises(ResultFileError, match="another run is writing"), results_directory(tmp_path):
            pass  # pragma: no cover
    with results_directory(tmp_path):  # released
        pass


def test_nan_survives_a_round_trip(tmp_path, make_result):
    result = make_result(failed=True)
    path = write_result(tmp_path, CaseSpec("log-barrier", "nominal", "ideal", 0), result)
    again = read_result(path)
    assert math.isnan(again.weight_error) and all(math.isnan(w) for w in again.weights)


def test_config_errors_are_algorithm_errors():
    with pytest.raises(AlgorithmError):
        CaseSpec("log-barrier", "nominal", "ideal", 0, {"n_random": -1})


def test_every_condition_of_every_suite_is_found_again_when_its_file_is_written(tmp_path, make_result):
    """A result written under any suite's condition name (``mass+20`` has a sign) is loaded back."""
    from ioc_bench.runner.results import load_results, write_result
    from ioc_bench.synthetic.case import CaseSpec
    from ioc_bench.synthetic.suites import SUITES

    conditions = sorted({c for suite in SUITES.values() for c in suite.conditions})
    for condition in conditions:
        write_result(tmp_path, CaseSpec("log-barrier", "nominal", condition, 0), make_result(condition=condition))
    assert sorted(r.condition for r in load_results(tmp_path)) == conditions


# -- a file is the case its name says ----------------------------------------------------------

REPO = Path(__file__).resolve().parents[2]


def test_the_result_files_in_the_repository_are_valid_cases():
    """Real files (two algorithms, default and non-default configs, distractor features) pass."""
    results = load_results(REPO / "docs" / "data" / "weight_floor")
    assert len(results) == 16 and {r.algorithm for r in results} == {"log-barrier", "analytic-center"}


def test_recorded_spec_is_the_case_the_content_says(make_result):
    result = make_result(weight_set="penalize-knee", condition="noise", seed=4, config={"n_random": 3})
    spec = recorded_spec(result)
    assert spec == CaseSpec("log-barrier", "penalize-knee", "noise", 4, {"n_random": 3})
    assert spec.key == "log-barrier/penalize-knee__noise__seed4__cfg" + spec.key[-8:]


@pytest.mark.parametrize(
    ("content", "named"),
    [
        ({"algorithm": "analytic-center"}, {}),
        ({"seed": 1}, {}),
        ({"weight_set": "penalize-hip"}, {}),
        ({"condition": "noise"}, {}),
        ({"config": {"n_random": 3}}, {}),
        ({}, {"config": {"n_random": 3}}),
    ],
)
def test_stored_result_is_never_another_case(tmp_path, make_result, content, named):
    """One algorithm's results under another's names are never taken as done."""
    spec = CaseSpec(**({"algorithm": "log-barrier", "weight_set": "nominal", "condition": "ideal", "seed": 0} | named))
    other = make_result(**content)
    spec.path(tmp_path).parent.mkdir(parents=True)
    spec.path(tmp_path).write_text(json.dumps(other.to_dict()))
    with pytest.raises(ResultFileError, match=r"holds the case .*, not the one its name says") as exc:
        stored_result(tmp_path, spec)
    assert str(spec.path(tmp_path)) in str(exc.value) and "\n" not in str(exc.value)
    with pytest.raises(ResultFileError, match="not the one its name says"):
        load_results(tmp_path)


def test_a_file_with_its_own_case_is_done(tmp_path, make_result):
    spec = CaseSpec("log-barrier", "nominal", "ideal", 0, {"n_random": 3})
    write_result(tmp_path, spec, make_result(config={"n_random": 3}))
    assert stored_result(tmp_path, spec) is not None
    assert stored_result(tmp_path, CaseSpec("log-barrier", "nominal", "ideal", 1)) is None


def test_a_case_key_or_case_config_that_disagrees_with_the_content_is_refused(tmp_path, make_result):
    spec = CaseSpec("log-barrier", "nominal", "ideal", 0)
    path = write_result(tmp_path, spec, make_result())
    data = json.loads(path.read_text())
    path.write_text(json.dumps(data | {"case_key": "log-barrier/nominal__ideal__seed9"}))
    with pytest.raises(ResultFileError, match="records case_key"):
        load_results(tmp_path)
    path.write_text(json.dumps(data | {"case_config": {"n_random": 3}}))
    with pytest.raises(ResultFileError, match=r"case_config .* is not its config's difference"):
        load_results(tmp_path)


def test_a_case_folder_leading_out_of_the_results_is_refused_before_and_at_writing(tmp_path, make_result):
    """A linked algorithm folder inside --out cannot make run write outside it."""
    root, outside = tmp_path / "results", tmp_path / "outside"
    root.mkdir()
    outside.mkdir()
    (root / "log-barrier").symlink_to(outside)
    spec = CaseSpec("log-barrier", "nominal", "ideal", 0)
    with pytest.raises(ResultFileError, match="leads out of"):
        stored_result(root, spec)  # what plan_run asks of every case before any work
    with pytest.raises(ResultFileError, match="leads out of"):
        write_result(root, spec, make_result())
    assert not any(outside.iterdir())
    (outside / spec.path(root).name).write_text(json.dumps(make_result().to_dict()))
    with pytest.raises(ResultFileError, match="leads out of"):
        load_results(root)


@pytest.mark.parametrize(
    ("make", "message"),
    [
        (lambda p: p.symlink_to("/etc/passwd"), "is a symbolic link"),
        (lambda p: p.symlink_to("/dev/zero"), "is a symbolic link"),
        (lambda p: os.mkfifo(p), "is a FIFO"),
        (lambda p: p.mkdir(), "is a directory"),
    ],
)
def test_result_names_that_are_not_regular_files_are_refused_by_name(tmp_path, make, message):
    """Links (to /etc/passwd, /dev/zero) are not read and a FIFO does not block the reader."""
    path = CaseSpec("log-barrier", "nominal", "ideal", 0).path(tmp_path)
    path.parent.mkdir()
    make(path)
    with pytest.raises(ResultFileError, match=message) as exc:
        load_results(tmp_path)
    assert str(path) in str(exc.value)


def test_a_case_name_too_long_for_the_file_system_is_refused_before_the_run(tmp_path):
    spec = CaseSpec("log-barrier", ",".join(["1.000000000000000"] * 2 + ["1" + "0" * 300]), "ideal", 0)
    with pytest.raises(ResultFileError, match="over the 255 a file name may have"):
        stored_result(tmp_path, spec)


_PROVENANCE = {"commit": "0123456789abcdef0123456789abcdef01234567", "dirty": False, "versions": {"numpy": "2.4.6"}}


@pytest.mark.parametrize(
    ("change", "message"),
    [
        ({"algorithm": "x/../../ESCAPED"}, "invalid algorithm name"),
        ({"weight_set": "nope"}, "unknown weight set"),
        ({"weight_set": "0,0,0"}, "must not all be zero"),
        ({"condition": "nope"}, "unknown condition"),
        ({"features": ["hip", "hip", "dtau"]}, "distinct known features"),
        ({"features": ["hip", "knee", "bogus"]}, "distinct known features"),
        ({"features": ["knee", "hip", "dtau"]}, "are not the ideal condition's"),
        ({"true_weights": [0.0, 0.0, 0.0]}, "are not the truth of weight set"),
        ({"true_weights": [-0.58, 0.58, 0.58]}, "are not the truth of weight set"),
        ({"weights": [0.0, 0.0, 0.0]}, "not all zero"),
        ({"weights": [-1.0, 1.0, 1.0]}, "non-negative"),
        ({"weights": [None, 1.0, 1.0]}, "finite"),
        ({"weight_error": -0.1}, "weight_error must be a number from 0 to 1"),
        ({"weight_error": None}, "weight_error must be a number from 0 to 1"),
        ({"trajectory_error": -1}, "trajectory_error must be a non-negative"),
        ({"found_trajectory_error": -1}, "found_trajectory_error must be a non-negative"),
        ({"wall_time": -1}, "wall_time must be a number from 0 to"),
        ({"wall_time": None}, "wall_time must be a number from 0 to"),
        ({"wall_time": 1e30}, "wall_time must be a number from 0 to"),
        ({"demo_speed": -0.27}, "demo_speed must be a non-negative"),
        ({"n_solves": -1}, "n_solves must be between 0 and"),
        ({"n_solves": 10**30}, "n_solves must be between 0 and"),
        ({"chosen_iteration": 3}, "chosen_iteration must index the history"),
        ({"chosen_iteration": -1}, "chosen_iteration must index the history"),
        ({"status": "a\nb"}, "status must be one line"),
        ({"status": ""}, "status must be one line"),
        ({"status": "x" * 501}, "status must be one line"),
        ({"demo_features": {"bogus": 1.0}}, "demo_features must map known features"),
        ({"wall_time": 10**400}, "wall_time must be a number"),
        ({"provenance": {"commit": None}}, r"provenance must be \{\} or have the fields commit, dirty, versions"),
        ({"provenance": _PROVENANCE | {"commit": "HEAD"}}, "provenance.commit must be null or 40 lower-case hex"),
        ({"provenance": _PROVENANCE | {"commit": "A" * 40}}, "provenance.commit must be null or 40 lower-case hex"),
        ({"provenance": _PROVENANCE | {"dirty": 1}}, "provenance.dirty must be null, true or false"),
        ({"provenance": _PROVENANCE | {"commit": None}}, "provenance.dirty must be null without a commit"),
        ({"provenance": _PROVENANCE | {"versions": {"numpy": None}}}, "provenance.versions must map"),
        ({"provenance": _PROVENANCE | {"versions": {"where": "/home/me/ioc"}}}, "without / or"),
        ({"provenance": _PROVENANCE | {"versions": {str(k): "1" for k in range(33)}}}, "at most 32 names"),
        ({"provenance": _PROVENANCE | {"versions": []}}, "provenance.versions must map"),
        ({"provenance": "abc"}, "provenance must be an object"),
    ],
)
def test_out_of_range_values_are_refused(make_result, change, message):
    """Negative errors, zero truths, unknown names and 10**30 solves are refused, never rendered."""
    with pytest.raises(ValueError, match=message) as exc:
        parse_result(make_result().to_dict() | change)
    assert "\n" not in str(exc.value) and len(str(exc.value)) < 400


def test_a_result_keeps_the_provenance_it_ran_with_and_one_without_it_has_none_recorded(tmp_path, make_result):
    spec = CaseSpec("log-barrier", "nominal", "ideal", 0)
    result = dataclasses.replace(make_result(), provenance=provenance())
    path = write_result(tmp_path, spec, result)
    assert read_result(path) == result and read_result(path).provenance == provenance()
    assert stored_result(tmp_path, spec) == result  # a case done stays done, whatever it ran with
    old = json.loads(path.read_text())
    del old["provenance"]
    assert parse_result(old).provenance == {}
    path.write_text(json.dumps(old | {"provenance": _PROVENANCE}))  # another commit: still this case, done
    assert stored_result(tmp_path, spec).provenance == _PROVENANCE


def test_a_case_records_the_provenance_of_the_process_that_ran_it():
    from ioc_bench.synthetic.case import failure

    assert failure(CaseSpec("log-barrier", "nominal", "ideal", 0), "timed out").provenance == provenance()


def test_a_failed_case_may_lack_its_estimate_and_a_huge_seed_is_a_seed(tmp_path, make_result):
    failed = make_result(failed=True)
    assert parse_result(json.loads(json.dumps(failed.to_dict()))).failed
    seed = 10**30  # seeds of any size are fine (NumPy takes them)
    spec = CaseSpec("log-barrier", "nominal", "ideal", seed)
    write_result(tmp_path, spec, make_result(seed=seed))
    assert stored_result(tmp_path, spec).seed == seed


def test_a_result_of_another_basis_is_named_by_it_and_read_back(tmp_path, make_result):
    from ioc_bench.runner.results import load_results, write_result
    from ioc_bench.synthetic.results import run_label, run_slug

    spec = CaseSpec("log-barrier", "penalize-work", "ideal", 0, basis="energetics")
    record = make_result(weight_set="penalize-work", basis="energetics")
    path = write_result(tmp_path, spec, record)
    assert path.name == "penalize-work__ideal__seed0__basis-energetics.json"
    (again,) = load_results(tmp_path)
    assert again.basis == "energetics" and again.features == ("hip", "knee", "dtau", "work", "collision")
    assert run_label(again) == "log-barrier (energetics)" and run_slug(again) == "log-barrier__basis-energetics"


def test_a_result_without_a_basis_is_of_the_effort_basis(make_result):
    from ioc_bench.synthetic.results import parse_result

    data = json.loads(json.dumps(make_result().to_dict()))
    del data["basis"]
    assert parse_result(data).basis == "effort"
    data["weight_set"] = "penalize-work"
    with pytest.raises(ValueError, match="penalize-work"):
        parse_result(data)
