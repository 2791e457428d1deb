"""The human track as the runner registers it: its records, its suites, its board section.

Named in :data:`ioc_bench.tracks.BUILTIN_TRACKS`; the runner loads it from there.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from ioc_bench.fileio import to_jsonable
from ioc_bench.human.board import SECTION
from ioc_bench.human.case import HumanCaseSpec, parse_record
from ioc_bench.human.record import TRACK as NAME
from ioc_bench.human.suites import HUMAN_SUITES
from ioc_bench.runner.protocol import Track
from ioc_bench.validation import shown


def recorded_case(record: Any, case_config: Mapping[str, Any] | None) -> HumanCaseSpec:
    """The case a record says it is; ``ValueError`` if ``case_config`` (as written) is not its config."""
    spec = HumanCaseSpec(**{name: getattr(record, name) for name in HumanCaseSpec.identity_fields()})
    if case_config is not None and to_jsonable(dict(case_config)) != to_jsonable(dict(spec.config)):
        raise ValueError(f"case_config {shown(dict(case_config))} is not the record's config {shown(spec.config)}")
    return spec


#: The human track.
TRACK = Track(NAME, parse_record, recorded_case, suites=HUMAN_SUITES, board=SECTION)
