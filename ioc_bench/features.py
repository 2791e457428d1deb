"""Cost features of a walking step (SPEC section 2), one definition for every user.

The trajectory optimizer puts these expressions in its objective symbolically; the IOC,
the scoring and the tables evaluate the very same functions on numbers. Each feature is a
function of :class:`FeatureInputs`, whose fields are CasADi matrices (``SX`` inside the
optimizer, ``DM`` on recorded trajectories).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

import casadi as ca
import numpy as np

from ioc_bench.model.linkage import Linkage
from ioc_bench.model.walker import ACTUATORS, WALKER_ROLES, GaitRoles
from ioc_bench.trajectory import Trajectory

#: Target step length of the ``steplen`` distractor (SPEC section 2).
STEPLEN_TARGET = 0.3
#: Scale of the torque-rate feature, "due to unit differences" (the paper).
DTAU_SCALE = 0.001


@dataclass(frozen=True)
class FeatureInputs:
    """What the features read from a step; T knots spaced ``dt`` apart.

    Attributes:
        dt: (T, 1) knot spacing, equal at every knot (a column, so that inside the
            optimizer each knot's terms depend on a local copy of the timestep).
        tau: (T, A) actuated torques, columns in :data:`ACTUATORS` order.
        torso: (T, 1) torso angle from vertical.
        foot_z: (T, 1) swing-foot height.
        step_length: swing-foot landing distance ahead of the stance foot (scalar).
    """

    dt: Any
    tau: Any
    torso: Any
    foot_z: Any
    step_length: Any


@dataclass(frozen=True)
class Feature:
    name: str
    description: str
    fn: Callable[[FeatureInputs], Any]


def _columns(prefix: str) -> list[int]:
    return [i for i, name in enumerate(ACTUATORS) if name.startswith(prefix)]


def _effort(prefix: str) -> Callable[[FeatureInputs], Any]:
    cols = _columns(prefix)
    return lambda f: _integral(f, ca.sum2(f.tau[:, cols] ** 2))


def _integral(f: FeatureInputs, values: Any) -> Any:
    """sum_t values_t dT over the knots."""
    return ca.dot(f.dt, values)


def _torque_rate(f: FeatureInputs) -> Any:
    diff = f.tau[1:, :] - f.tau[:-1, :]
    return DTAU_SCALE * ca.sum1(ca.sum2(diff**2) / f.dt[:-1])


FEATURES: dict[str, Feature] = {
    f.name: f
    for f in (
        Feature("hip", "sum_t (tau_hip_swing^2 + tau_hip_stance^2) dT", _effort("hip")),
        Feature("knee", "sum_t (tau_knee_swing^2 + tau_knee_stance^2) dT", _effort("knee")),
        Feature("dtau", "0.001 sum_t sum_j ((tau_j,t+1 - tau_j,t) / dT)^2 dT", _torque_rate),
        Feature("torso", "sum_t theta_torso^2 dT", lambda f: _integral(f, f.torso**2)),
        Feature("steplen", "(step length - 0.3)^2", lambda f: (f.step_length - STEPLEN_TARGET) ** 2),
        Feature("footheight", "mean swing-foot height", lambda f: ca.sum1(f.foot_z) / f.foot_z.shape[0]),
    )
}
#: The three effort features that generate the demonstrations, in weight order.
COST_FEATURES: tuple[str, ...] = ("hip", "knee", "dtau")
#: Distractors: offered to the IOC in the distractor condition, true weight 0.
DISTRACTORS: tuple[str, ...] = ("torso", "steplen", "footheight")
ALL_FEATURES: tuple[str, ...] = COST_FEATURES + DISTRACTORS


def check_names(names: Sequence[str]) -> tuple[str, ...]:
    """Validate feature names, raising ``ValueError`` that lists the valid ones."""
    unknown = [n for n in names if n not in FEATURES]
    if unknown or not names:
        raise ValueError(f"unknown feature(s) {unknown or names}; valid: {', '.join(FEATURES)}")
    return tuple(names)


def feature_expressions(inputs: FeatureInputs, names: Sequence[str] = ALL_FEATURES) -> list[Any]:
    """The named features of ``inputs`` (symbolic or numeric), in order."""
    return [FEATURES[n].fn(inputs) for n in check_names(names)]


def trajectory_inputs(traj: Trajectory, linkage: Linkage, roles: GaitRoles = WALKER_ROLES) -> FeatureInputs:
    """Numeric :class:`FeatureInputs` of a recorded trajectory."""
    foot = traj.point(linkage, *roles.swing_foot)
    return FeatureInputs(
        dt=ca.DM.ones(traj.n_knots) * traj.dt,
        tau=ca.DM(traj.tau),
        torso=ca.DM(traj.q[:, linkage.index(roles.torso), 2]),
        foot_z=ca.DM(foot[:, 1]),
        step_length=float(foot[-1, 0]),
    )


def evaluate(
    traj: Trajectory,
    linkage: Linkage,
    names: Sequence[str] = ALL_FEATURES,
    roles: GaitRoles = WALKER_ROLES,
) -> dict[str, float]:
    """Feature values of a trajectory, by name."""
    values = feature_expressions(trajectory_inputs(traj, linkage, roles), names)
    return {n: float(np.asarray(ca.DM(v)).item()) for n, v in zip(names, values)}
