"""The synthetic track as the runner registers it: its records, its suites, its board section.

Its records name no track (they predate the others): a record without ``track`` is this
track's. Named in :data:`ioc_bench.tracks.BUILTIN_TRACKS`; the runner loads it from there.
"""

from __future__ import annotations

from ioc_bench.runner.protocol import Track
from ioc_bench.synthetic.board import SECTION
from ioc_bench.synthetic.results import parse_result, recorded_spec
from ioc_bench.synthetic.suites import SUITES

#: The synthetic track.
TRACK = Track("synthetic", parse_result, recorded_spec, suites=SUITES, board=SECTION, names_itself=False)
