"""The compass walker with a torso: two rigid legs and a torso, hip torques only.

A second, simpler planar linkage built through the same code as the 5-segment walker
(it keeps the generic-linkage promise of :mod:`ioc_bench.model.linkage`). Its NLP is
smaller, so it also serves users and tests as a fast model. Without knees its swing foot
passes the stance foot at ground level: like every compass gait, it scuffs at mid-stance
(the model allows the foot at height 0 without force).
"""

from __future__ import annotations

import numpy as np

from ioc_bench.model.gait_model import GaitModel, GaitRoles, GuessShape, stance_swing_angles
from ioc_bench.model.linkage import Joint, Linkage, Pin, Segment
from ioc_bench.model.params import CompassParams

COMPASS_ROLES = GaitRoles(
    contact_pin="ground",
    swing_foot=("leg_swing", "foot"),
    stance_foot=("leg_stance", "foot"),
    swap_segments=(("leg_stance", "leg_swing"),),
    swap_joints=(("hip_stance", "hip_swing"),),
    torso="torso",
)


def compass_linkage(params: CompassParams | None = None) -> Linkage:
    """The compass walker as a planar linkage, stance foot pinned at the origin."""
    p = params or CompassParams()
    torso = Segment("torso", p.torso.mass, p.torso.inertia, {"hip": (-p.torso.com, 0.0)})
    leg = {"hip": (p.leg.com, 0.0), "foot": (p.leg.com - p.leg.length, 0.0)}
    segments = (
        torso,
        Segment("leg_stance", p.leg.mass, p.leg.inertia, leg),
        Segment("leg_swing", p.leg.mass, p.leg.inertia, leg),
    )
    pins = (
        Pin("hip_stance", "leg_stance", "hip", "torso", "hip"),
        Pin("hip_swing", "leg_swing", "hip", "torso", "hip"),
        Pin("ground", "leg_stance", "foot", None, (0.0, 0.0)),
    )
    joints = (Joint("hip_stance", "torso", "leg_stance"), Joint("hip_swing", "torso", "leg_swing"))
    return Linkage(segments, pins, joints, gravity=p.gravity)


def _guess_angles(linkage: Linkage, params: CompassParams, shape: GuessShape, s: np.ndarray) -> np.ndarray:
    stance, swing, _ = stance_swing_angles(shape.step, params.leg_length, s)
    theta = np.zeros((len(s), len(linkage.segments)))
    theta[:, linkage.index("torso")] = shape.lean
    theta[:, linkage.index("leg_stance")] = stance
    theta[:, linkage.index("leg_swing")] = swing
    return theta


COMPASS = GaitModel(
    name="compass",
    linkage=compass_linkage,
    default_params=CompassParams(),
    params_from_dict=CompassParams.from_dict,
    roles=COMPASS_ROLES,
    actuator_groups={"hip": ("hip_stance", "hip_swing")},
    guess_angles=_guess_angles,
)
