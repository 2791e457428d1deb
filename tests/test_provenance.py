"""A record's provenance: the commit and versions its case ran with, checked when read back,
summarised on a board."""

from __future__ import annotations

import re
import subprocess
from types import SimpleNamespace

import pytest

from ioc_bench import provenance as prov
from ioc_bench.provenance import (
    FIELDS,
    PACKAGES,
    check_provenance,
    provenance,
    provenance_line,
    summarise_provenance,
)

COMMIT = "0123456789abcdef0123456789abcdef01234567"
OTHER = "89abcdef0123456789abcdef0123456789abcdef"


@pytest.fixture
def fresh():
    """Provenance computed again in this test (and again after it)."""
    prov._provenance.cache_clear()
    yield
    prov._provenance.cache_clear()


def test_this_checkout_records_its_commit_and_the_versions():
    p = provenance()
    assert tuple(p) == FIELDS
    assert re.fullmatch(r"[0-9a-f]{40}", p["commit"])  # the tests run from a git checkout
    assert isinstance(p["dirty"], bool)
    assert set(p["versions"]) == {"python", "platform", *PACKAGES}
    assert all(isinstance(v, str) and "/" not in v for v in p["versions"].values())
    check_provenance(p)


def test_it_is_computed_once_and_handed_out_as_a_copy():
    first = provenance()
    first["versions"]["numpy"] = "edited"
    assert provenance()["versions"]["numpy"] != "edited"
    assert prov._provenance.cache_info().currsize == 1


def test_without_git_there_is_no_commit(fresh, monkeypatch):
    def no_git(*args, **kwargs):
        raise FileNotFoundError("git")

    monkeypatch.setattr(subprocess, "run", no_git)
    p = provenance()
    assert p["commit"] is None and p["dirty"] is None and p["versions"]["python"]
    check_provenance(p)


def test_a_copy_lying_untracked_in_another_repository_has_no_commit(fresh, monkeypatch, tmp_path):
    """An installed copy in some repository's ignored folder (a venv in a checkout) is not that repository's."""
    git = ["git", "-c", "user.name=t", "-c", "user.email=t@t", "-c", "init.defaultBranch=main"]
    subprocess.run([*git, "init", "-q", str(tmp_path)], check=True)
    (tmp_path / "README").write_text("x")
    subprocess.run([*git, "-C", str(tmp_path), "add", "README"], check=True)
    subprocess.run([*git, "-C", str(tmp_path), "commit", "-q", "-m", "x"], check=True)
    (tmp_path / "ioc_bench").mkdir()
    (tmp_path / "ioc_bench" / "__init__.py").write_text("")
    monkeypatch.setattr(prov, "_source_root", lambda: tmp_path)
    assert provenance()["commit"] is None
    subprocess.run([*git, "-C", str(tmp_path), "add", "ioc_bench"], check=True)
    subprocess.run([*git, "-C", str(tmp_path), "commit", "-q", "-m", "y"], check=True)
    prov._provenance.cache_clear()
    tracked = provenance()
    assert re.fullmatch(r"[0-9a-f]{40}", tracked["commit"]) and tracked["dirty"] is False
    (tmp_path / "README").write_text("changed")
    prov._provenance.cache_clear()
    assert provenance()["dirty"] is True


@pytest.mark.parametrize(
    ("value", "message"),
    [
        ({"commit": COMMIT}, r"provenance must be \{\} or have the fields commit, dirty, versions"),
        ({"commit": COMMIT, "dirty": False, "versions": {}, "host": "x"}, "must be {} or have the fields"),
        ({"commit": COMMIT[:12], "dirty": False, "versions": {}}, "commit must be null or 40 lower-case hex"),
        ({"commit": 5, "dirty": False, "versions": {}}, "commit must be null or 40 lower-case hex"),
        ({"commit": COMMIT, "dirty": "yes", "versions": {}}, "dirty must be null, true or false"),
        ({"commit": None, "dirty": True, "versions": {}}, "dirty must be null without a commit"),
        ({"commit": None, "dirty": None, "versions": {"numpy": "2\n"}}, "versions must map"),
        ({"commit": None, "dirty": None, "versions": {"numpy": "x" * 101}}, "at most 100 characters"),
        ({"commit": None, "dirty": None, "versions": {"src": "C:\\ioc"}}, "without / or"),
        (None, "provenance must be an object"),
    ],
)
def test_a_malformed_provenance_is_refused_in_one_line(value, message):
    with pytest.raises(ValueError, match=message) as exc:
        check_provenance(value)
    assert "\n" not in str(exc.value) and len(str(exc.value)) < 400


def test_none_recorded_and_an_unknown_commit_are_provenances():
    check_provenance({})
    check_provenance({"commit": None, "dirty": None, "versions": {"python": "3.11.7"}})


def _record(commit=None, dirty=None, **versions):
    return SimpleNamespace(provenance={"commit": commit, "dirty": dirty, "versions": versions} if versions else {})


def test_a_board_counts_the_commits_and_version_sets_its_cases_ran_with():
    records = [
        _record(COMMIT, False, numpy="2.4.6"),
        _record(COMMIT, False, numpy="2.4.6"),
        _record(COMMIT, True, numpy="2.4.6"),
        _record(OTHER, False, numpy="2.5.0"),
        _record(None, None, numpy="2.5.0"),
        _record(),
        SimpleNamespace(),  # a record type without the field: not recorded either
    ]
    summary = summarise_provenance(records)
    assert summary["cases"] == 7 and summary["not_recorded"] == 2
    assert summary["commits"] == [
        {"commit": COMMIT, "dirty": False, "cases": 2},
        {"commit": None, "dirty": None, "cases": 1},
        {"commit": COMMIT, "dirty": True, "cases": 1},
        {"commit": OTHER, "dirty": False, "cases": 1},
    ]
    assert summary["versions"] == [
        {"versions": {"numpy": "2.4.6"}, "cases": 3},
        {"versions": {"numpy": "2.5.0"}, "cases": 2},
    ]
    line = provenance_line(summary)
    assert "\n" not in line and line.startswith("**Cases ran with:** commit `0123456789ab` (2 cases)")
    assert "`0123456789ab` with uncommitted changes (1 case)" in line
    assert "unknown (not a git checkout) (1 case)" in line
    assert "**Versions:** numpy 2.4.6 (3 cases); numpy 2.5.0 (2 cases); not recorded (2 cases)" in line


def test_a_board_of_old_records_says_their_provenance_was_not_recorded():
    line = provenance_line(summarise_provenance([_record(), _record()]))
    assert line == "**Cases ran with:** commit not recorded (2 cases). **Versions:** not recorded (2 cases)"
