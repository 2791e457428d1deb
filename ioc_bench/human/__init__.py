"""Real human walking for the benchmark: the WBDS treadmill trials as walker steps.

``wbds`` reads and checks the data set's ASCII layout, ``anthropometry`` builds the
subject's walker, ``step`` maps a trial to one symmetric step in the walker's units, and
``observe`` turns it into an :class:`~ioc_bench.trajectory.Observation` that holds only what
was measured, on the walker or another model the step maps to (``models``: the walker with
rolling feet, on the subject's body). The track itself: ``case`` (a case of the benchmark's case protocol: a cost
inferred at some speeds, its steps predicted at the others), ``scoring`` (the RMSEs, the
copy baseline, the adaptation and ground-force errors), ``record`` (what a result file
holds, checked when read), ``summary`` (a run per algorithm and design), ``opening`` (the
board's ranked summary, headline and figures), ``board`` (the track's leaderboard section),
``suites`` (the case lists as data), ``figures`` and ``track`` (the track as the runner
registers it); these bring in the solvers and are imported on their own. ``docs/human.md``
says how each choice was made and what it costs.
"""

from ioc_bench.human.anthropometry import BodyLengths, SubjectBody, subject_body, subject_walker
from ioc_bench.human.observe import human_observation, measured_mask, segment_rmse_deg, walker_ground_force
from ioc_bench.human.step import LEG_SEGMENTS, GroundForces, HumanStep, StepChecks, human_step
from ioc_bench.human.wbds import WbdsData, WbdsDataError, WbdsTrial, shipped_folder


def load_step(subject: str, speed_code: str, data: WbdsData | None = None, **kwargs) -> HumanStep:
    """The mapped step of ``subject`` at ``speed_code`` (shipped data by default);
    keyword arguments go to :func:`human_step`."""
    return human_step((data or WbdsData()).trial(subject, speed_code), **kwargs)


__all__ = [
    "LEG_SEGMENTS",
    "BodyLengths",
    "GroundForces",
    "HumanStep",
    "StepChecks",
    "SubjectBody",
    "WbdsData",
    "WbdsDataError",
    "WbdsTrial",
    "human_observation",
    "human_step",
    "load_step",
    "measured_mask",
    "segment_rmse_deg",
    "shipped_folder",
    "subject_body",
    "subject_walker",
    "walker_ground_force",
]
