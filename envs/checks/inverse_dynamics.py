"""Check 1, inverse dynamics: does MuJoCo's model need the optimizer's torques for the optimizer's motion?

MuJoCo's ``mj_inverse`` on every knot's state and acceleration, with constraints
(contacts, limits) disabled, must give the optimizer's joint torques (actuators plus
knee-locks) plus the stance foot's ground force mapped through the Jacobian of the point
where it acts, ``J_foot^T F_ground``: the foot point, or the lowest point of a rolling arc
(radius from the gait model's linkage, ``envs.physics.foot_roll``). The root DOFs carry no
actuator, so their residual must vanish too.
Figure of merit: ``max |residual| / max |tau|`` over knots and DOFs. Matching models give
~1e-12; a model with 10 % heavier legs gives several hundred percent (the
demonstrations' torques are small, ~0.06 m g L, while a mass error shifts forces by
~0.01 m g). No time integration is involved, so the physics timestep does not enter.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import mujoco
import numpy as np

from envs.coordinates import generalized_torques
from envs.physics import MujocoParams, Physics, check_physics, foot_contact_point, foot_roll
from envs.reference import DemoReference
from ioc_bench.demo import Demonstration
from ioc_bench.model.catalogue import get_model
from ioc_bench.model.mjcf import JOINTS
from ioc_bench.model.walker import ACTUATORS

#: Inverse-dynamics residual above which the models are judged different (relative to peak torque).
ID_TOLERANCE = 1e-3


@dataclass(frozen=True, eq=False)
class InverseDynamicsResult:
    """MuJoCo's inverse dynamics against the optimizer's torques and ground force.

    Attributes:
        residual: (T, 7) ``qfrc_inverse - (joint torques + J_foot^T F_ground)`` per knot and DOF.
        peak_torque: max |actuated torque| of the demonstration.
        max_residual: max |residual|.
        relative_residual: ``max_residual / peak_torque``.
        worst_knot: knot of the largest residual.
        worst_dof: DOF (joint name) of the largest residual.
        tolerance: relative residual at or above which the check fails.
    """

    residual: np.ndarray
    peak_torque: float
    max_residual: float
    relative_residual: float
    worst_knot: int
    worst_dof: str
    tolerance: float = ID_TOLERANCE

    @property
    def passed(self) -> bool:
        return bool(self.relative_residual < self.tolerance)

    def to_dict(self) -> dict[str, Any]:
        return {
            "relative_residual": self.relative_residual,
            "max_residual": self.max_residual,
            "peak_torque": self.peak_torque,
            "worst_knot": self.worst_knot,
            "worst_dof": self.worst_dof,
            "tolerance": self.tolerance,
            "passed": self.passed,
        }


def inverse_dynamics_check(
    demo: Demonstration,
    params: MujocoParams | None = None,
    tolerance: float = ID_TOLERANCE,
    *,
    physics: Physics | None = None,
) -> InverseDynamicsResult:
    """Compare MuJoCo's inverse dynamics with the demonstration's torques at every knot.

    Args:
        demo: the demonstration.
        params: the model MuJoCo uses (default: the demonstration's own). Another model
            (say the nominal one for a heavy-legs demonstration) must fail the check.
        tolerance: relative residual at or above which the check fails.
        physics: the compiled model of ``params`` shared by a replay's checks (None: built here).
    """
    p = params or demo.params
    physics = check_physics(physics, p)
    model, data = physics.model, physics.data
    ref, tr = DemoReference.of(demo), demo.trajectory
    shank, roll = int(model.site_bodyid[model.site("foot_a").id]), foot_roll(p)
    ground = ref.linkage.pin_index(get_model(demo.model).roles.contact_pin)
    knees = [ACTUATORS.index(j.name) for j in ref.linkage.locked]
    jac = np.zeros((3, model.nv))
    residual = np.zeros((tr.n_knots, model.nv))
    for k in range(tr.n_knots):
        data.qpos[:], data.qvel[:], data.qacc[:] = ref.qpos[k], ref.qvel[k], ref.qacc[k]
        mujoco.mj_inverse(model, data)
        mujoco.mj_jac(model, data, jac, None, foot_contact_point(model, data, "a", roll), shank)
        joint = tr.tau[k].copy()
        joint[knees] += tr.lock[k]
        fx, fz = tr.pin_forces[k, ground]
        residual[k] = data.qfrc_inverse - (generalized_torques(joint, "a") + jac[0] * fx + jac[2] * fz)
    peak = float(np.max(np.abs(tr.tau)))
    worst = np.unravel_index(int(np.argmax(np.abs(residual))), residual.shape)
    max_res = float(np.abs(residual).max())
    return InverseDynamicsResult(
        residual=residual,
        peak_torque=peak,
        max_residual=max_res,
        relative_residual=max_res / peak if peak > 0 else float("inf"),
        worst_knot=int(worst[0]),
        worst_dof=JOINTS[int(worst[1])],
        tolerance=tolerance,
    )
