"""The 5-segment walker as a planar linkage, and the roles its parts play in a step.

Legs are named by role in the step, not by side: the stance leg is pinned to the ground
at its foot, the swing leg lands at the end of the step, and at heel strike the two swap
(the relabelling that makes the gait periodic).
"""

from __future__ import annotations

from ioc_bench.model.gait_model import GaitModel, GaitRoles, kneed_guess_angles
from ioc_bench.model.linkage import Joint, Linkage, Pin, Segment
from ioc_bench.model.params import SegmentParams, WalkerParams

#: Actuated joints, in the order torques are stored everywhere (trajectories, MuJoCo).
ACTUATORS: tuple[str, ...] = ("hip_stance", "hip_swing", "knee_stance", "knee_swing")
#: Knees carrying the passive lock, in storage order.
LOCKS: tuple[str, ...] = ("knee_stance", "knee_swing")
#: Pins in storage order (pin forces, impulses); "ground" holds the stance foot.
PINS: tuple[str, ...] = ("hip_stance", "hip_swing", "knee_stance", "knee_swing", "ground")
#: Segments in storage order.
SEGMENTS: tuple[str, ...] = ("torso", "thigh_stance", "shank_stance", "thigh_swing", "shank_swing")


WALKER_ROLES = GaitRoles(
    contact_pin="ground",
    swing_foot=("shank_swing", "foot"),
    stance_foot=("shank_stance", "foot"),
    swap_segments=(("thigh_stance", "thigh_swing"), ("shank_stance", "shank_swing")),
    swap_joints=(("hip_stance", "hip_swing"), ("knee_stance", "knee_swing")),
    torso="torso",
)


def _stick(name: str, seg: SegmentParams, proximal: str, distal: str, com_below: bool) -> Segment:
    """A stick segment; its axis points from the distal to the proximal end."""
    if com_below:  # legs: proximal end at the top
        points = {proximal: (seg.com, 0.0), distal: (seg.com - seg.length, 0.0)}
    else:  # torso: proximal end (hip) at the bottom
        points = {proximal: (-seg.com, 0.0), distal: (seg.length - seg.com, 0.0)}
    return Segment(name, seg.mass, seg.inertia, points)


def walker_linkage(params: WalkerParams | None = None) -> Linkage:
    """The walker (``docs/spec.md``, "The walker") as a planar linkage, stance foot pinned at the origin."""
    p = params or WalkerParams()
    segments = (
        _stick("torso", p.torso, "hip", "shoulder", com_below=False),
        _stick("thigh_stance", p.thigh, "hip", "knee", com_below=True),
        _stick("shank_stance", p.shank, "knee", "foot", com_below=True),
        _stick("thigh_swing", p.thigh, "hip", "knee", com_below=True),
        _stick("shank_swing", p.shank, "knee", "foot", com_below=True),
    )
    pins = (
        Pin("hip_stance", "thigh_stance", "hip", "torso", "hip"),
        Pin("hip_swing", "thigh_swing", "hip", "torso", "hip"),
        Pin("knee_stance", "shank_stance", "knee", "thigh_stance", "knee"),
        Pin("knee_swing", "shank_swing", "knee", "thigh_swing", "knee"),
        Pin("ground", "shank_stance", "foot", None, (0.0, 0.0)),
    )
    joints = (
        Joint("hip_stance", "torso", "thigh_stance"),
        Joint("hip_swing", "torso", "thigh_swing"),
        Joint("knee_stance", "thigh_stance", "shank_stance", lock=True),
        Joint("knee_swing", "thigh_swing", "shank_swing", lock=True),
    )
    linkage = Linkage(segments, pins, joints, gravity=p.gravity)
    assert tuple(s.name for s in linkage.segments) == SEGMENTS
    assert tuple(j.name for j in linkage.actuated) == ACTUATORS
    assert tuple(j.name for j in linkage.locked) == LOCKS
    assert tuple(p.name for p in linkage.pins) == PINS
    return linkage


#: The 5-segment walker of ``docs/spec.md``, "The walker" (the benchmark's model).
WALKER = GaitModel(
    name="walker",
    linkage=walker_linkage,
    default_params=WalkerParams(),
    params_from_dict=WalkerParams.from_dict,
    roles=WALKER_ROLES,
    actuator_groups={"hip": ("hip_stance", "hip_swing"), "knee": ("knee_stance", "knee_swing")},
    guess_angles=kneed_guess_angles,
)
