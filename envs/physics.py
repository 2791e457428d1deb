"""The MuJoCo walker: model construction and the few queries the env and replays share.

Feet and ground as the trajectory optimizer models them: the ground holds the **stance**
foot (a pin whose force stays inside the friction cone) and takes the landing at heel
strike; it never acts on the swing foot, which the optimizer lets touch the ground at
height 0 mid-swing with no force. The environment therefore gives the swing foot a
frictionless contact (normal force only, MuJoCo ``condim`` 1) and the stance foot the
generated model's friction (``condim`` 3, coefficient ``params.friction``), swapping the
two when the roles swap at a heel strike (:func:`set_stance_friction`). The feet get
contact priority over the floor so that their own ``condim`` decides (MuJoCo otherwise
takes the larger of the two geoms'). The measurements: docs/notes/2026-11-25-grazing-swing-feet.md.

Both MuJoCo models (:mod:`ioc_bench.model.mjcf`: the walker's point feet, the
``rolling-feet`` walker's rolling spheres) share one layout; where a foot meets the
ground is read from the gait model's linkage (:func:`foot_roll`), never retyped.
"""

from __future__ import annotations

from dataclasses import dataclass

import mujoco
import numpy as np

from ioc_bench.model.catalogue import model_of
from ioc_bench.model.feet import FootedParams
from ioc_bench.model.mjcf import LEGS, ContactSettings, model_mjcf
from ioc_bench.model.params import WalkerParams

#: Parameters of the gait models that have a MuJoCo model.
MujocoParams = WalkerParams | FootedParams

#: The environment's physics: the generated model's contact settings with RK4 steps of
#: 0.002 (Walker2d-v5's). Measured against 0.0005 (the MJCF default, which the open-loop
#: check keeps): the closed-loop check's feedback shares agree within 0.021 on eight
#: demonstrations, the inverse-dynamics check does not integrate, the stance contact and
#: penetration are unchanged, and random play is as stable; steps/s roughly triple
#: (docs/environment.md, ``benchmarks/physics_step.py``). The contact time constant
#: (0.004) stays at MuJoCo's lower limit of two timesteps.
DEFAULT_CONTACT = ContactSettings(timestep=0.002)
#: MuJoCo contact dimensionality of the stance foot (normal force and friction in the plane).
STANCE_CONDIM = 3
#: MuJoCo contact dimensionality of the swing foot: normal force only, no friction.
SWING_CONDIM = 1


def build_model(params: MujocoParams | None = None, contact: ContactSettings | None = None) -> mujoco.MjModel:
    """The compiled MuJoCo model for ``params`` (default: the walker of ``docs/spec.md``,
    "Segment parameters"; a rolling-feet ``FootedParams``: the walker with rolling feet).

    ``contact`` defaults to :data:`DEFAULT_CONTACT`, the environment's physics. ``ValueError``
    in one line for the parameters of a gait model without a MuJoCo model (``ankle-feet``).
    """
    return mujoco.MjModel.from_xml_string(model_mjcf(params or WalkerParams(), contact or DEFAULT_CONTACT))


@dataclass(frozen=True, eq=False)
class Physics:
    """The MuJoCo model of one set of parameters, compiled once, with its data: what a
    replay's physical checks share (each used to compile its own from the MJCF).

    Constraints are disabled: the checks evaluate inverse dynamics (which must not see
    contacts or limits) and forward kinematics (which never does); none integrates. Each
    check sets the state it reads (``qpos``, ``qvel``, ``qacc``) at every knot before asking.
    """

    params: MujocoParams
    model: mujoco.MjModel
    data: mujoco.MjData

    @classmethod
    def of(cls, params: MujocoParams) -> Physics:
        """The checks' model of ``params`` and its data."""
        model = build_model(params)
        model.opt.disableflags |= mujoco.mjtDisableBit.mjDSBL_CONSTRAINT
        return cls(params, model, mujoco.MjData(model))


def check_physics(physics: Physics | None, params: MujocoParams) -> Physics:
    """``physics`` if it is the model of ``params`` (built now if None); ``ValueError`` if
    it is another's, so a check never judges a demonstration against the wrong model."""
    if physics is None:
        return Physics.of(params)
    if physics.params is not params and physics.params.to_dict() != params.to_dict():
        raise ValueError("the MuJoCo physics given is of other parameters than the check's")
    return physics


def foot_roll(params: MujocoParams) -> float:
    """Radius of the stance foot's rolling arc in the gait model's linkage (0: a point foot).

    The site ``foot_<leg>`` is the linkage's foot point (the arc's centre), so the ground
    contact, where the ground force acts, lies this far below it.
    """
    model = model_of(params)
    segment, point = model.roles.stance_foot
    return float(model.linkage(params).segment(segment).rolls.get(point, 0.0))


def foot_contact_point(model: mujoco.MjModel, data: mujoco.MjData, leg: str, roll: float) -> np.ndarray:
    """World position of where leg ``leg``'s foot meets the ground (kinematics computed):
    the foot site, or the lowest point of its rolling arc of radius ``roll``."""
    return data.site(f"foot_{leg}").xpos - np.array([0.0, 0.0, roll])


def foot_geoms(model: mujoco.MjModel) -> dict[str, int]:
    """Leg -> the geom id of its foot (the only geoms that collide with the floor)."""
    return {leg: model.geom(f"foot_{leg}").id for leg in LEGS}


def give_feet_priority(model: mujoco.MjModel) -> None:
    """Let the feet's own contact settings decide their contacts with the floor.

    MuJoCo combines two geoms' ``condim`` by their maximum unless one has the higher
    priority; with priority 1 on the feet, :func:`set_stance_friction` decides each foot's.
    The feet and the floor share solref, solimp and friction coefficient, so nothing else changes.
    """
    for gid in foot_geoms(model).values():
        model.geom_priority[gid] = 1


def set_stance_friction(model: mujoco.MjModel, stance_leg: str) -> None:
    """Friction on the stance foot, none on the swing foot (see the module docstring)."""
    for leg, gid in foot_geoms(model).items():
        model.geom_condim[gid] = STANCE_CONDIM if leg == stance_leg else SWING_CONDIM


def foot_in_contact(model: mujoco.MjModel, data: mujoco.MjData, leg: str) -> bool:
    """Whether leg ``leg``'s foot touches the floor."""
    gid = model.geom(f"foot_{leg}").id
    return bool(np.any(data.contact.geom[: data.ncon] == gid))


@dataclass(frozen=True)
class HealthyRange:
    """When the walker counts as standing: hip height and torso angle within range.

    Attributes:
        hip_z: (min, max) hip height in leg lengths.
        torso_angle: (min, max) torso angle from vertical, rad.
    """

    hip_z: tuple[float, float] = (0.6, 2.0)
    torso_angle: tuple[float, float] = (-1.0, 1.0)

    def fall_reason(self, qpos: np.ndarray) -> str | None:
        """None while healthy, else a short reason naming the violated range."""
        z, angle = float(qpos[1]), float(qpos[2])
        if not self.hip_z[0] <= z <= self.hip_z[1]:
            return f"hip height {z:.3f} outside {self.hip_z}"
        if not self.torso_angle[0] <= angle <= self.torso_angle[1]:
            return f"torso angle {angle:.3f} rad outside {self.torso_angle}"
        return None
