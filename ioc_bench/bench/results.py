"""Result files: one JSON per case, named by the case, written atomically.

Layout: ``<results>/<algorithm>/<weight_set>__<condition>__seed<k>[__cfg<hash>].json``.
A file exists only once its case has finished (successfully or not), so a directory of
results is always a consistent record to resume from or to summarise.
"""

from __future__ import annotations

import hashlib
import json
import os
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from ioc_bench.bench.case import CaseResult
from ioc_bench.fileio import atomic_write_json


@dataclass(frozen=True)
class CaseSpec:
    """What identifies a case (everything ``run_case`` needs)."""

    algorithm: str
    weight_set: str
    condition: str
    seed: int
    config: Mapping[str, Any] = field(default_factory=dict)

    @property
    def key(self) -> str:
        """Relative path of the case's result file, without suffix."""
        name = f"{_safe(self.weight_set)}__{self.condition}__seed{self.seed}"
        if self.config:
            digest = hashlib.sha256(json.dumps(dict(self.config), sort_keys=True).encode()).hexdigest()[:8]
            name += f"__cfg{digest}"
        return f"{self.algorithm}/{name}"

    def path(self, root: str | os.PathLike) -> Path:
        return Path(root) / f"{self.key}.json"


def _safe(text: str) -> str:
    return "".join(c if c.isalnum() or c in "-._" else "_" for c in text)


def write_result(root: str | os.PathLike, spec: CaseSpec, result: CaseResult) -> Path:
    data = result.to_dict() | {"case_key": spec.key, "case_config": dict(spec.config)}
    return atomic_write_json(spec.path(root), data)


def read_result(path: str | os.PathLike) -> CaseResult:
    """Load one result file; raises ``ValueError`` naming the file if it is not one."""
    try:
        data = json.loads(Path(path).read_text())
        data.pop("case_key", None)
        data.pop("case_config", None)
        return CaseResult.from_dict(data)
    except (OSError, ValueError, TypeError) as exc:
        raise ValueError(f"{path} is not a case result: {exc}") from None


def is_done(root: str | os.PathLike, spec: CaseSpec) -> bool:
    """A case is done when its result file exists and reads back."""
    path = spec.path(root)
    if not path.is_file():
        return False
    try:
        read_result(path)
    except ValueError:
        return False
    return True


def load_results(root: str | os.PathLike) -> list[CaseResult]:
    """Every case result under ``root`` (unreadable files raise, naming the file)."""
    root = Path(root)
    if not root.is_dir():
        raise ValueError(f"results directory not found: {root}")
    return [read_result(p) for p in sorted(root.rglob("*.json"))]
