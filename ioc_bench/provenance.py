"""Where a record came from: the commit and the package versions a case ran with.

Every case record (:class:`~ioc_bench.synthetic.case.CaseResult`,
:class:`~ioc_bench.human.record.HumanResult`) carries :func:`provenance` as it was when the
case ran, in the process that ran it: ``{"commit", "dirty", "versions"}``. ``commit`` is the
full SHA-1 of the git checkout ioc_bench was imported from (None if it is not one, e.g. an
installed wheel, or git is not there), ``dirty`` whether tracked files had uncommitted
changes then (None without a commit), ``versions`` Python's and the packages' versions and
the platform (never a host name or a path). A record without it (made before it was
recorded) reads as ``{}``: not recorded.

A leaderboard states what its cases ran with (:func:`summarise_provenance`,
:func:`provenance_line`), not what the machine that drew it has installed.
"""

from __future__ import annotations

import copy
import functools
import importlib.metadata
import os
import platform
import re
import subprocess
from collections import Counter
from collections.abc import Iterable
from pathlib import Path
from typing import Any

from ioc_bench.validation import shown

#: The packages whose versions a record carries, beside Python's and the platform's.
PACKAGES = ("ioc-bench", "casadi", "numpy", "scipy", "mujoco", "gymnasium")
#: The fields of a recorded provenance (an empty one is "not recorded").
FIELDS = ("commit", "dirty", "versions")
#: Most entries a recorded ``versions`` may hold, and the longest name or version.
MAX_VERSIONS, MAX_VERSION_TEXT = 32, 100
#: Seconds a git command may take before the commit counts as unknown.
GIT_TIMEOUT = 5.0
#: The schema ``leaderboard.json`` names, and its version (2: provenance of the cases, not
#: the versions of the machine that drew the board).
LEADERBOARD_SCHEMA, LEADERBOARD_SCHEMA_VERSION = "ioc-bench/leaderboard", 2
#: What a board says of cases whose records carry no provenance.
NOT_RECORDED = "not recorded"

_COMMIT = re.compile(r"[0-9a-f]{40}")
#: A name or version: one line, no path separator (no machine path reaches a board).
_VERSION_TEXT = re.compile(rf"[^\x00-\x1f\x7f/\\]{{1,{MAX_VERSION_TEXT}}}")


def versions() -> dict[str, str]:
    """Python's version, the platform (system, release, machine; no host name) and
    :data:`PACKAGES`' versions (``not installed`` for one that is not)."""
    out = {"python": platform.python_version(), "platform": platform.platform(terse=True)}
    for pkg in PACKAGES:
        try:
            out[pkg] = importlib.metadata.version(pkg)
        except importlib.metadata.PackageNotFoundError:
            out[pkg] = "not installed"
    return out


def provenance() -> dict[str, Any]:
    """This process's provenance (a fresh copy; computed once per process)."""
    return copy.deepcopy(_provenance())


@functools.cache
def _provenance() -> dict[str, Any]:
    commit = _commit()
    return {"commit": commit, "dirty": None if commit is None else _dirty(), "versions": versions()}


def _source_root() -> Path:
    """The folder holding the ``ioc_bench`` package (a checkout's root, or site-packages)."""
    return Path(__file__).resolve().parent.parent


def _git(*args: str) -> str | None:
    """``git args`` in :func:`_source_root`, its output stripped; None on any failure."""
    env = {k: v for k, v in os.environ.items() if not k.startswith("GIT_")}  # no GIT_DIR pointing elsewhere
    try:
        done = subprocess.run(
            ["git", *args],
            cwd=_source_root(),
            capture_output=True,
            text=True,
            timeout=GIT_TIMEOUT,
            env=env,
            check=False,
        )
    except (OSError, subprocess.SubprocessError, ValueError):
        return None
    return done.stdout.strip() if done.returncode == 0 else None


def _commit() -> str | None:
    """The commit checked out where ioc_bench's source lies, if the package is tracked there
    (an installed copy inside some other repository's ignored folder has no commit)."""
    commit = _git("rev-parse", "HEAD")
    if commit is None or not _COMMIT.fullmatch(commit):
        return None
    package = Path(__file__).resolve().parent.name
    if _git("ls-files", "--error-unmatch", "--", f"{package}/__init__.py") is None:
        return None
    return commit


def _dirty() -> bool | None:
    """Whether tracked files differ from the commit (None if git cannot say)."""
    status = _git("status", "--porcelain", "--untracked-files=no")
    return None if status is None else bool(status)


def check_provenance(value: Any, where: str = "provenance") -> None:
    """``ValueError`` (one line) unless ``value`` is a recorded provenance: ``{}`` (not
    recorded), or exactly :data:`FIELDS` with ``commit`` null or 40 hex digits, ``dirty``
    null or a boolean (null without a commit), and ``versions`` at most
    :data:`MAX_VERSIONS` names mapped to versions, each one line of text without a path
    separator."""
    if not isinstance(value, dict):
        raise ValueError(f"{where} must be an object, got {shown(value)}")
    if not value:
        return
    if set(value) != set(FIELDS):
        raise ValueError(
            f"{where} must be {{}} or have the fields {', '.join(FIELDS)}, got {shown(sorted(map(str, value)))}"
        )
    commit, dirty, recorded = (value[k] for k in FIELDS)
    if commit is not None and not (isinstance(commit, str) and _COMMIT.fullmatch(commit)):
        raise ValueError(f"{where}.commit must be null or 40 lower-case hex digits, got {shown(commit)}")
    if dirty is not None and not isinstance(dirty, bool):
        raise ValueError(f"{where}.dirty must be null, true or false, got {shown(dirty)}")
    if commit is None and dirty is not None:
        raise ValueError(f"{where}.dirty must be null without a commit, got {shown(dirty)}")
    if (
        not isinstance(recorded, dict)
        or len(recorded) > MAX_VERSIONS
        or not all(_version_text(k) and _version_text(v) for k, v in recorded.items())
    ):
        raise ValueError(
            f"{where}.versions must map at most {MAX_VERSIONS} names to versions, each one line of at most "
            f"{MAX_VERSION_TEXT} characters without / or \\, got {shown(recorded)}"
        )


def _version_text(value: Any) -> bool:
    return isinstance(value, str) and bool(_VERSION_TEXT.fullmatch(value))


# -- what a board's cases ran with -----------------------------------------------------------------


def summarise_provenance(records: Iterable[Any]) -> dict[str, Any]:
    """What ``records`` ran with: ``cases``; ``not_recorded``, the cases without provenance;
    ``commits``, each distinct ``(commit, dirty)`` with its case count; ``versions``, each
    distinct set of versions with its case count (most cases first)."""
    recorded = [getattr(r, "provenance", None) or {} for r in records]
    known = [p for p in recorded if p]
    commits = Counter((p["commit"], p["dirty"]) for p in known)
    sets = Counter(tuple(sorted(p["versions"].items())) for p in known)
    shown_as = {tuple(sorted(p["versions"].items())): p["versions"] for p in reversed(known)}  # as first recorded
    return {
        "cases": len(recorded),
        "not_recorded": len(recorded) - len(known),
        "commits": [
            {"commit": commit, "dirty": dirty, "cases": n}
            for (commit, dirty), n in sorted(commits.items(), key=lambda kv: (-kv[1], kv[0][0] or "", str(kv[0][1])))
        ],
        "versions": [
            {"versions": dict(shown_as[items]), "cases": n}
            for items, n in sorted(sets.items(), key=lambda kv: (-kv[1], kv[0]))
        ],
    }


def provenance_line(summary: dict[str, Any]) -> str:
    """:func:`summarise_provenance` as one Markdown line: the commits, then the version sets,
    each with its case count (``not recorded`` for records made before provenance was)."""
    missing = summary["not_recorded"]
    commits = [f"{_commit_text(c['commit'], c['dirty'])} ({_cases(c['cases'])})" for c in summary["commits"]]
    sets = [
        ", ".join(f"{k} {v}" for k, v in s["versions"].items()) + f" ({_cases(s['cases'])})"
        for s in summary["versions"]
    ]
    if missing:
        commits.append(f"{NOT_RECORDED} ({_cases(missing)})")
        sets.append(f"{NOT_RECORDED} ({_cases(missing)})")
    return f"**Cases ran with:** commit {'; '.join(commits) or 'none'}. **Versions:** {'; '.join(sets) or 'none'}"


def _commit_text(commit: str | None, dirty: bool | None) -> str:
    if commit is None:
        return "unknown (not a git checkout)"
    return f"`{commit[:12]}`" + (" with uncommitted changes" if dirty else "")


def _cases(n: int) -> str:
    return f"{n} case{'' if n == 1 else 's'}"


__all__ = ["check_provenance", "provenance", "provenance_line", "summarise_provenance", "versions"]
