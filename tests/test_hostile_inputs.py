"""Hypothesis strategies for hostile inputs, and the properties every reader and
writer must hold for them.

Strategies:

- :func:`case_identities`: what names a case (algorithm, weight set, condition, seed, config),
  drawn over every condition, the paper's weight sets and numeric ones, seeds up to 10**30.
- :func:`spoilt_fields`: one field of a result record made wrong (typed wrong, out of range,
  unknown, or naming a path), with the words the refusal must contain.
- :func:`hostile_paths`: a path a command must refuse before any work, as a recipe that
  :func:`make_path` builds in a scratch folder (empty, NUL, long names, long paths, pseudo-file
  systems, link loops, dangling links, links to /proc or out of a tree, FIFOs, devices,
  folders, files where a folder is needed).

Properties: a valid record round-trips and is its own case; a spoilt record, a record filed
under another case's name, or a hostile path is refused with one ``ValueError`` line, leaving
the scratch folder as it was; ``Task`` takes every positive finite real and refuses the rest;
JSON of any depth is a value or a ``ValueError``.
"""

from __future__ import annotations

import json
import math
import os
import stat
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st

from ioc_bench.cli import main
from ioc_bench.paths import (
    PathError,
    check_input_file,
    check_inside,
    check_output_dir,
    check_output_file,
    read_bytes,
)
from ioc_bench.runner.results import ResultFileError, load_results, stored_result, write_result
from ioc_bench.synthetic.case import CaseSpec
from ioc_bench.synthetic.conditions import CONDITIONS
from ioc_bench.synthetic.results import parse_result
from ioc_bench.task import Task
from ioc_bench.validation import MAX_JSON_DEPTH, load_json
from ioc_bench.weights import WEIGHT_SETS

FIXTURES = settings(suppress_health_check=[HealthCheck.function_scoped_fixture], max_examples=40)

# -- strategies: result files ------------------------------------------------------------------


def case_identities() -> st.SearchStrategy[dict]:
    """Keyword arguments of a case (and of ``synthetic_result``): every identity field."""
    numeric = st.tuples(*[st.integers(1, 20)] * 3).map(lambda w: ",".join(map(str, w)))
    algorithm_config = st.sampled_from(["log-barrier", "analytic-center"]).flatmap(
        lambda a: st.tuples(st.just(a), st.just({}) | st.builds(lambda n: {"n_random": n}, st.integers(0, 9)))
    )
    return st.builds(
        lambda ac, ws, cond, seed: {
            "algorithm": ac[0],
            "config": ac[1],
            "weight_set": ws,
            "condition": cond,
            "seed": seed,
        },
        algorithm_config,
        st.sampled_from(list(WEIGHT_SETS)) | numeric,
        st.sampled_from(list(CONDITIONS)),
        st.integers(0, 3) | st.integers(0, 10**30),
    )


_PATHLIKE_NAMES = st.sampled_from(["x/../../ESCAPED", "../x", "a/b", ".hidden", "", "a b", "..", "/etc/passwd"])
_UNKNOWN = st.text("abcxyz-_", min_size=1, max_size=12).filter(lambda t: t not in CONDITIONS and t not in WEIGHT_SETS)
_NEGATIVE = st.floats(max_value=-1e-12, allow_nan=False, allow_infinity=False)
_BEYOND = st.integers(10**9 + 1, 10**40)


def spoilt_fields() -> st.SearchStrategy[tuple[str, object, str]]:
    """(field, bad value, words the refusal contains) for one field of a result record."""
    return st.one_of(
        st.tuples(st.just("algorithm"), _PATHLIKE_NAMES, st.just("invalid algorithm name")),
        st.tuples(st.just("condition"), _UNKNOWN, st.just("unknown condition")),
        st.tuples(st.just("weight_set"), _UNKNOWN, st.just("unknown weight set")),
        st.tuples(st.just("seed"), st.integers(max_value=-1), st.just("seed must be")),
        st.tuples(st.just("n_solves"), _BEYOND | st.integers(max_value=-1), st.just("n_solves must be between")),
        st.tuples(st.just("wall_time"), _NEGATIVE, st.just("wall_time must be")),
        st.tuples(st.just("weight_error"), _NEGATIVE | st.floats(1.0001, 1e300), st.just("weight_error must be")),
        st.tuples(st.just("trajectory_error"), _NEGATIVE, st.just("trajectory_error must be")),
        st.tuples(st.just("demo_speed"), _NEGATIVE, st.just("demo_speed must be")),
        st.tuples(st.just("status"), st.text(min_size=501) | st.just("a\nb") | st.just(""), st.just("status must be")),
        st.tuples(st.just("features"), st.sampled_from([["hip", "hip", "dtau"], ["hip", "x", "y"]]), st.just("feat")),
        st.tuples(st.just("true_weights"), st.just([0.0, 0.0, 0.0]), st.just("true_weights")),
        st.tuples(st.just("chosen_iteration"), st.integers(3, 10**6) | st.integers(max_value=-1), st.just("chosen_")),
        st.tuples(st.just("notes"), st.integers(MAX_JSON_DEPTH + 1, 5000).map(_nested), st.just("nested deeper")),
    )  # fmt: skip


def _nested(depth: int) -> str:
    """Marker for a JSON value ``depth`` levels deep (spliced in as text: json.dumps would recurse)."""
    return f"@nested:{depth}"


def _record_text(data: dict) -> str:
    """``data`` as JSON text, with ``@nested:N`` markers replaced by N-deep arrays."""
    text = json.dumps(data, allow_nan=True)
    for value in data.values():
        if isinstance(value, str) and value.startswith("@nested:"):
            depth = int(value.split(":")[1])
            text = text.replace(json.dumps(value), "[" * depth + "]" * depth)
    return text


# -- strategies: paths ---------------------------------------------------------------------------

#: Recipes of paths every output check must refuse, and what the refusal says.
_OUTPUT_RECIPES = {
    "empty": "empty string",
    "nul": "NUL character",
    "long-name": "a file name may have",
    "long-path": "a path may have",
    "pseudo": "not a place for files",
    "link-to-pseudo": "not a place for files",
    "loop": "symbolic link loop",
    "dangling": "symbolic link to nothing",
    "under-file": "is not a directory",
}
#: ... and paths a reader must refuse (it reads regular files only).
_INPUT_RECIPES = {
    "empty": "empty string",
    "nul": "NUL character",
    "long-name": "a file name may have",
    "pseudo": "not a place for files",
    "link-to-pseudo": "not a place for files",
    "loop": "symbolic link loop",
    "dangling": "not found",
    "fifo": "is a FIFO",
    "folder": "is a directory",
    "missing": "not found",
}


#: Places on pseudo-file systems: folders (outputs go below them) and files (read as they are).
PSEUDO_FOLDERS = ["/proc", "/sys", "/dev", "/proc/self", "/sys/kernel"]
PSEUDO_FILES = ["/dev/zero", "/dev/urandom", "/proc/self/status", "/proc/self/environ", "/sys/kernel/address_bits"]


def hostile_paths(recipes: dict[str, str], pseudo: list[str] = PSEUDO_FOLDERS) -> st.SearchStrategy:
    """(recipe, a size parameter, the pseudo-file system place used) drawn from ``recipes``."""
    return st.tuples(st.sampled_from(sorted(recipes)), st.integers(0, 40), st.sampled_from(pseudo))


def make_path(tmp: Path, recipe: tuple[str, int, str], suffix: str = "") -> str:
    """Build ``recipe`` under ``tmp`` (links, FIFOs, folders) and return the hostile path.

    ``suffix`` ends the path's last name (``.npz`` for ``gait``, which would add it): the
    path is hostile with it, not made harmless by it.
    """
    kind, n, pseudo = recipe
    if kind == "empty":
        return ""
    if kind == "nul":
        return str(tmp / ("x" * n + "\0y" + suffix))
    if kind == "long-name":
        return str(tmp / ("n" * (256 + 10 * n) + suffix))
    if kind == "long-path":
        return str(tmp / "/".join(["d" * 200] * (21 + n % 5))) + suffix
    if kind == "pseudo":
        return pseudo if pseudo in PSEUDO_FILES else f"{pseudo}/ioc-bench-{n}/out{suffix}"
    if kind == "link-to-pseudo":
        (tmp / f"to-pseudo-{n}{suffix}").symlink_to(pseudo)
        return str(tmp / f"to-pseudo-{n}{suffix}") + ("" if pseudo in PSEUDO_FILES else f"/x{suffix}")
    if kind == "loop":
        chain = [tmp / f"loop{n}-{i}{suffix}" for i in range(1 + n % 4)]
        for a, b in zip(chain, chain[1:] + chain[:1]):
            a.symlink_to(b)
        return str(chain[0] / f"x{suffix}" if n % 2 else chain[0])
    if kind == "dangling":
        (tmp / f"dangling-{n}{suffix}").symlink_to(tmp / "nothing")
        return str(tmp / f"dangling-{n}{suffix}")
    if kind == "under-file":
        (tmp / f"file-{n}").write_text("x")
        return str(tmp / f"file-{n}" / "sub" / f"out{suffix}")
    if kind == "fifo":
        os.mkfifo(tmp / f"fifo-{n}{suffix}")
        return str(tmp / f"fifo-{n}{suffix}")
    if kind == "folder":
        (tmp / f"folder-{n}{suffix}").mkdir()
        return str(tmp / f"folder-{n}{suffix}")
    if kind == "missing":
        return str(tmp / f"missing-{n}{suffix}")
    raise KeyError(kind)


def _tree(root: Path) -> dict[str, int]:
    """Every name under ``root`` with its file type (what a refused call must not change)."""
    return {
        str(Path(d) / n): stat.S_IFMT(os.lstat(Path(d) / n).st_mode)
        for d, dirs, names in os.walk(root)
        for n in dirs + names
    }


# -- properties: result files -------------------------------------------------------------------


@FIXTURES
@given(identity=case_identities(), failed=st.booleans())
def test_property_a_valid_record_round_trips_and_is_its_own_case(tmp_path_factory, make_result, identity, failed):
    root = tmp_path_factory.mktemp("valid")
    spec = CaseSpec(**identity)
    write_result(root, spec, make_result(**identity, failed=failed))
    (loaded,) = load_results(root)
    assert (loaded.algorithm, loaded.weight_set, loaded.condition, loaded.seed) == (
        spec.algorithm,
        spec.weight_set,
        spec.condition,
        spec.seed,
    )
    assert stored_result(root, spec) is not None


@FIXTURES
@given(identity=case_identities(), spoilt=spoilt_fields())
def test_property_a_spoilt_record_is_refused_with_one_line_naming_the_file(
    tmp_path_factory, make_result, identity, spoilt
):
    field, value, words = spoilt
    root = tmp_path_factory.mktemp("spoilt")
    spec = CaseSpec(**identity)
    path = write_result(root, spec, make_result(**identity))
    path.write_text(_record_text(json.loads(path.read_text()) | {field: value}))
    with pytest.raises(ResultFileError) as exc:
        load_results(root)
    message = str(exc.value)
    assert str(path) in message and "\n" not in message and len(message) <= 400 + len(str(path)), message
    assert words in message, message


@FIXTURES
@given(a=case_identities(), b=case_identities())
def test_property_a_record_under_another_case_name_is_refused(tmp_path_factory, make_result, a, b):
    """A file holding another algorithm's or seed's case is not taken as done, nor counted twice."""
    spec_a, spec_b = CaseSpec(**a), CaseSpec(**b)
    assume(spec_a.key != spec_b.key)
    root = tmp_path_factory.mktemp("swapped")
    spec_b.path(root).parent.mkdir(parents=True)
    spec_b.path(root).write_text(json.dumps(make_result(**a).to_dict()))
    with pytest.raises(ResultFileError, match="not the one its name says"):
        stored_result(root, spec_b)
    with pytest.raises(ResultFileError, match="not the one its name says"):
        load_results(root)


@given(data=st.dictionaries(st.text(max_size=5), st.floats() | st.integers() | st.none(), max_size=6))
def test_property_any_flat_record_reads_or_raises_value_error(data):
    try:
        parse_result(data)
    except ValueError:
        return
    pytest.fail("a random object was read as a result")  # pragma: no cover


# -- properties: paths --------------------------------------------------------------------------


@FIXTURES
@given(recipe=hostile_paths(_OUTPUT_RECIPES), as_file=st.booleans())
def test_property_a_hostile_output_path_is_refused_and_nothing_is_made(tmp_path_factory, recipe, as_file):
    tmp = tmp_path_factory.mktemp("out")
    path = make_path(tmp, recipe)
    before = _tree(tmp)
    check = check_output_file if as_file else check_output_dir
    with pytest.raises(PathError) as exc:
        check(path)
    assert _OUTPUT_RECIPES[recipe[0]] in str(exc.value) and "\n" not in str(exc.value)
    assert _tree(tmp) == before


@FIXTURES
@given(recipe=hostile_paths(_INPUT_RECIPES, PSEUDO_FILES))
def test_property_a_hostile_input_path_is_refused_without_blocking(tmp_path_factory, recipe):
    tmp = tmp_path_factory.mktemp("in")
    path = make_path(tmp, recipe)
    for read in (lambda p: check_input_file(p), lambda p: read_bytes(p, 1 << 20)):
        with pytest.raises(PathError) as exc:
            read(path)  # a FIFO opened for reading without O_NONBLOCK would hang here
        assert _INPUT_RECIPES[recipe[0]] in str(exc.value), str(exc.value)


@FIXTURES
@given(depth=st.integers(1, 6), escape=st.sampled_from(["..", "out", "to-proc"]))
def test_property_links_never_lead_a_tree_outside_itself(tmp_path_factory, depth, escape):
    tmp = tmp_path_factory.mktemp("tree")
    root = tmp / "root"
    inner = root.joinpath(*[f"d{i}" for i in range(depth)])
    inner.mkdir(parents=True)
    (root / "out").symlink_to(tmp)
    (root / "to-proc").symlink_to("/proc/self")
    assert check_inside(root, inner / "x.json")
    escaping = root / escape / "x" if escape != ".." else inner.joinpath(*[".."] * (depth + 1), "x")
    with pytest.raises(PathError, match="leads out of"):
        check_inside(root, escaping)


#: Commands and where each takes a path (``{p}`` is the hostile path; ``{res}`` a good results folder).
_COMMANDS = [
    "gait --out {p.npz}",  # gait adds .npz to a name without it
    "ioc --out {p}",
    "run --out {p}",
    "replay {p}",
    "leaderboard {res} --out {p}",
    "figures {res} --out {p}",
    "leaderboard {p}",
    "figures {p}",
    "compare {res} {p}",
    "compare {p} {res}",
    "human --subject WBDS01 --train T05 --predict T04 --out {p}",
    "human --subject WBDS01 --train T05 --predict T04 --data {p}",
]


@FIXTURES
@given(command=st.sampled_from(_COMMANDS), recipe=hostile_paths(_OUTPUT_RECIPES))
def test_property_every_command_refuses_a_hostile_path_before_any_work(
    tmp_path_factory, make_result, command, recipe, capsys, monkeypatch
):
    from ioc_bench.runner import run as runner
    from ioc_bench.trajopt.forward_problem import ForwardProblem

    def forbidden(*args, **kwargs):
        raise AssertionError("expensive work started before the path was checked")

    for owner, name in ((runner, "prepare_inputs"), (ForwardProblem, "solve"), (ForwardProblem, "__init__")):
        monkeypatch.setattr(owner, name, forbidden)
    tmp = tmp_path_factory.mktemp("cli")
    res = tmp / "results"
    write_result(res, CaseSpec("log-barrier", "nominal", "ideal", 0), make_result())
    suffix = ".npz" if "{p.npz}" in command else ""
    path = make_path(tmp, recipe, suffix)
    argv = [a.replace("{p.npz}", path).replace("{p}", path).replace("{res}", str(res)) for a in command.split()]
    before = _tree(tmp)
    capsys.readouterr()
    with pytest.raises(SystemExit) as exc:
        main(argv)
    err = capsys.readouterr().err
    assert exc.value.code == 2 and err.count("\n") == 1 and "Traceback" not in err, err
    assert _tree(tmp) == before


# -- properties: numbers and JSON ---------------------------------------------------------------


@given(
    speed=st.floats(1e-3, 10.0),
    kind=st.sampled_from([float, np.float16, np.float32, np.float64, np.longdouble]),
)
def test_property_task_takes_every_positive_finite_real(speed, kind):
    """Every positive finite real is a speed, NumPy scalars included (``Task(np.float32(0.27))`` is 0.27)."""
    value = kind(speed)
    assume(0 < float(value) < math.inf)
    task = Task(value)
    assert type(task.speed) is float and task.speed > 0
    if kind is np.float32:
        assert task.speed == float(str(value))  # 0.27, not 0.27000001072883606


@given(
    bad=st.one_of(
        st.integers(max_value=0),
        st.integers(min_value=10**309, max_value=10**1000),
        st.sampled_from([math.nan, math.inf, -math.inf, np.float32("nan"), np.float64(-1.0), True, np.True_]),
        st.text(max_size=5),
        st.none(),
        st.lists(st.floats(), max_size=2),
    )
)
def test_property_task_refuses_the_rest_naming_the_argument(bad):
    with pytest.raises(ValueError, match="speed must be a positive finite number") as exc:
        Task(bad)
    assert len(str(exc.value)) < 200
    if bad is not None:  # no step length is a task too
        with pytest.raises(ValueError, match="step_length must be a positive finite number"):
            Task(0.27, step_length=bad)


@given(depth=st.integers(1, 300_000), bracket=st.sampled_from(["[]", "{}"]))
def test_property_json_of_any_depth_is_a_value_or_a_value_error(depth, bracket):
    text = "[" * depth + "]" * depth if bracket == "[]" else '{"a":' * depth + "1" + "}" * depth
    try:
        load_json(text)
    except ValueError as exc:
        assert depth > MAX_JSON_DEPTH - (bracket == "{}") and "nested deeper" in str(exc)
    else:
        assert depth <= MAX_JSON_DEPTH
