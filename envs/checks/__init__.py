"""The MuJoCo checks of a demonstration, one module each, and all of them at once.

1. :mod:`~envs.checks.inverse_dynamics`: MuJoCo's inverse dynamics against the optimizer's
   torques (the models agree).
2. :mod:`~envs.checks.open_loop`: the step simulated with its torques alone (reported).
3. :mod:`~envs.checks.closed_loop`: the gait walked by :class:`envs.TrackingPolicy`
   through ``env.step`` for several steps.

The demonstration as the checks read it is :class:`envs.reference.Reference`; the figure
and GIF are in :mod:`envs.plots`.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from envs.checks.closed_loop import (
    DEFAULT_STEPS,
    FEEDBACK_SHARE_LIMIT,
    ClosedLoopResult,
    closed_loop_replay,
    track_demonstrations,
)
from envs.checks.inverse_dynamics import ID_TOLERANCE, InverseDynamicsResult, inverse_dynamics_check
from envs.checks.open_loop import OpenLoopResult, open_loop_replay
from envs.tracking import PDGains
from ioc_bench.demo import Demonstration
from ioc_bench.model.params import WalkerParams


@dataclass(frozen=True, eq=False)
class ReplayReport:
    """The three checks of one demonstration against one MuJoCo model."""

    inverse_dynamics: InverseDynamicsResult
    open_loop: OpenLoopResult
    closed_loop: ClosedLoopResult

    @property
    def passed(self) -> bool:
        """Inverse dynamics and closed loop pass (the open loop is reported, not judged)."""
        return self.inverse_dynamics.passed and self.closed_loop.passed

    def to_dict(self) -> dict[str, Any]:
        return {
            "inverse_dynamics": self.inverse_dynamics.to_dict(),
            "open_loop": self.open_loop.to_dict(),
            "closed_loop": self.closed_loop.to_dict(),
            "passed": self.passed,
        }


def replay(
    demo: Demonstration,
    steps: int = DEFAULT_STEPS,
    params: WalkerParams | None = None,
    gains: PDGains | None = None,
) -> ReplayReport:
    """Run the three checks of ``demo`` against the MuJoCo model of ``params`` (default: its own)."""
    return ReplayReport(
        inverse_dynamics=inverse_dynamics_check(demo, params),
        open_loop=open_loop_replay(demo, params),
        closed_loop=closed_loop_replay(demo, steps, gains, params),
    )


__all__ = [
    "DEFAULT_STEPS",
    "FEEDBACK_SHARE_LIMIT",
    "ID_TOLERANCE",
    "ClosedLoopResult",
    "InverseDynamicsResult",
    "OpenLoopResult",
    "ReplayReport",
    "closed_loop_replay",
    "inverse_dynamics_check",
    "open_loop_replay",
    "replay",
    "track_demonstrations",
]
