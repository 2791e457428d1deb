"""The MuJoCo checks of a demonstration, one module each, and all of them at once.

1. :mod:`~envs.checks.physics_checks`: the verdict, one check per way a gait can be
   physically wrong (torques inconsistent with the dynamics, motion inconsistent with its
   timing, a ground force that pulls or leaves the friction cone, a swing foot below the
   ground, a knee beyond its range), each a figure against a limit.
   :mod:`~envs.checks.inverse_dynamics` has the details of the first.
2. :mod:`~envs.checks.open_loop`: the step simulated with its torques alone (reported).
3. :mod:`~envs.checks.closed_loop`: the gait walked by :class:`envs.TrackingPolicy`
   through ``env.step`` for several steps (reported: walking is unstable, and a gait that
   falls or needs much feedback is unstable, not physically wrong).

The demonstration as the checks read it is :class:`envs.reference.DemoReference`; the figure
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
from envs.checks.physics_checks import (
    INEQUALITY_TOL,
    TIMING_TOL,
    PhysicsCheck,
    ground_force_checks,
    knee_range_check,
    penetration_check,
    physics_checks,
    stance_ground_forces,
    time_consistency_check,
)
from envs.physics import MujocoParams, Physics
from envs.tracking import PDGains
from ioc_bench.demo import Demonstration
from ioc_bench.model.mjcf import MJCF_MODELS


@dataclass(frozen=True, eq=False)
class ReplayReport:
    """The physical checks of one demonstration against one MuJoCo model, and its replays.

    Attributes:
        checks: the physical verdict, one :class:`PhysicsCheck` each.
        inverse_dynamics: details of the inverse-dynamics check (residual per knot and DOF).
        open_loop: the step simulated with its torques alone (reported); None if not replayed.
        closed_loop: the gait walked under tracking (reported: steps walked, feedback share);
            None if not replayed.
        replay_error: why the step could not be replayed (e.g. a motion so wrong that its
            hip does not move steadily forward, which the tracking policy needs), or None.
    """

    checks: tuple[PhysicsCheck, ...]
    inverse_dynamics: InverseDynamicsResult
    open_loop: OpenLoopResult | None
    closed_loop: ClosedLoopResult | None
    replay_error: str | None = None

    @property
    def passed(self) -> bool:
        """Every physical check passes; the open and closed loops are reported, not judged."""
        return all(c.passed for c in self.checks)

    @property
    def failures(self) -> tuple[PhysicsCheck, ...]:
        """The physical checks that failed."""
        return tuple(c for c in self.checks if not c.passed)

    def check(self, name: str) -> PhysicsCheck:
        """The physical check called ``name``; ``KeyError`` if there is none."""
        for c in self.checks:
            if c.name == name:
                return c
        raise KeyError(name)

    def to_dict(self) -> dict[str, Any]:
        return {
            "checks": [c.to_dict() for c in self.checks],
            "inverse_dynamics": self.inverse_dynamics.to_dict(),
            "open_loop": None if self.open_loop is None else self.open_loop.to_dict(),
            "closed_loop": None if self.closed_loop is None else self.closed_loop.to_dict(),
            "replay_error": self.replay_error,
            "passed": self.passed,
        }


#: The gait models that have a MuJoCo model (``ioc_bench.model.mjcf``) to check and replay in.
REPLAYABLE_MODELS = MJCF_MODELS


def check_replayable(demo: Demonstration) -> None:
    """``ValueError`` unless ``demo``'s gait model has a MuJoCo model (the other models of the
    catalogue have none yet: their demonstrations are verified by the optimizer only)."""
    if demo.model not in REPLAYABLE_MODELS:
        models = " and ".join(REPLAYABLE_MODELS)
        raise ValueError(
            f"a demonstration of the {demo.model!r} model cannot be replayed: only the {models} models have a "
            "MuJoCo model so far"
        )


def replay(
    demo: Demonstration,
    steps: int = DEFAULT_STEPS,
    params: MujocoParams | None = None,
    gains: PDGains | None = None,
) -> ReplayReport:
    """Check ``demo`` against the MuJoCo model of ``params`` (default: its own), and replay it.

    The physical checks share one compiled model (:class:`envs.physics.Physics`, built once
    here); the open and closed loops simulate in environments of their own (their timesteps
    differ and the environment switches the feet's friction as it walks).
    The physical checks always run. A step that cannot be replayed (``ValueError`` from
    the open or closed loop, e.g. a motion the tracking policy cannot follow by phase) is
    reported with its reason in :attr:`ReplayReport.replay_error`, not raised: the verdict
    is the physical checks'.

    Raises:
        ValueError: if ``steps < 1``, or if ``demo`` is of a gait model that has no MuJoCo model.
    """
    if steps < 1:
        raise ValueError(f"steps must be >= 1, got {steps}")
    check_replayable(demo)
    physics = Physics.of(params or demo.params)
    inverse_dynamics = inverse_dynamics_check(demo, params, physics=physics)
    checks = physics_checks(demo, inverse_dynamics, params, physics=physics)
    try:
        open_loop, closed_loop = open_loop_replay(demo, params), closed_loop_replay(demo, steps, gains, params)
    except ValueError as exc:
        return ReplayReport(checks, inverse_dynamics, None, None, str(exc))
    return ReplayReport(checks, inverse_dynamics, open_loop, closed_loop)


__all__ = [
    "DEFAULT_STEPS",
    "FEEDBACK_SHARE_LIMIT",
    "ID_TOLERANCE",
    "INEQUALITY_TOL",
    "REPLAYABLE_MODELS",
    "TIMING_TOL",
    "ClosedLoopResult",
    "InverseDynamicsResult",
    "OpenLoopResult",
    "PhysicsCheck",
    "ReplayReport",
    "check_replayable",
    "closed_loop_replay",
    "ground_force_checks",
    "inverse_dynamics_check",
    "knee_range_check",
    "open_loop_replay",
    "penetration_check",
    "physics_checks",
    "replay",
    "stance_ground_forces",
    "time_consistency_check",
    "track_demonstrations",
]
