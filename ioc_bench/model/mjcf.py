"""The walker as a MuJoCo model (MJCF), generated from the same :class:`WalkerParams`.

The optimizer and MuJoCo must describe one and the same walker, so the MJCF is built in
code from the parameters (``docs/spec.md``, "The walker"): a model variant such as
``WalkerParams().with_leg_mass_scale(1.1)`` gives the matching MuJoCo model with no
extra code. This module only writes a string; it does not import MuJoCo. Two gait models of
the catalogue have a MuJoCo model, the walker and ``rolling-feet`` (:data:`MJCF_MODELS`);
the others (``compass``, ``ankle-feet``) are refused by name (:func:`check_mjcf_model`).

Layout (every element named; each motor shares its joint's name):

- body ``torso``, whose origin is the **hip** (where both thighs attach), with three root
  joints: ``rootx`` (slide along x), ``rootz`` (slide along z), ``rooty`` (hinge about
  +y). So ``qpos[:3]`` is the hip's world x, z and the torso angle from vertical.
- legs ``a`` and ``b``: ``thigh_a`` hangs from the hip on hinge ``hip_a``; ``shank_a``
  hangs from the knee on hinge ``knee_a`` with range ``[0, knee_max_flexion]`` (no
  hyperextension; the limit is the passive knee-lock); the point foot (geom and site
  ``foot_a``) is the shank's distal end. The same for ``b``. A demonstration's stance and
  swing roles map onto the physical legs and swap at each heel strike.
- ``qpos = qvel index order = JOINTS = (rootx, rootz, rooty, hip_a, knee_a, hip_b, knee_b)``.
- motors ``MOTORS = (hip_a, hip_b, knee_a, knee_b)``: the ``ACTUATORS`` order with leg
  ``a`` in the stance role; ``ctrlrange = +-max_torque``, gear 1.

Conventions match :mod:`ioc_bench.model.linkage`: x forward, z up, angles about +y (a
segment's axis is ``(sin theta, cos theta)``), joint angle ``theta_child - theta_parent``,
a joint torque acts ``+tau`` on the child. In a body frame the segment axis is +z, so a
hanging leg's centre of mass sits at ``(0, 0, -com)`` and the torso's at ``(0, 0, com)``.

Inertia: each body has an explicit ``<inertial>`` with the parameters' mass and centre of
mass, and the parameters' inertia about y. The walker only rotates about y; the x and z entries
are those of a thin rod along the body axis (``Ixx = Iyy``, ``Izz = 1e-3 Iyy``), the
smallest choice MuJoCo accepts (it requires ``Ixx + Izz >= Iyy``). No joint has damping or
armature, so MuJoCo's rigid-body dynamics equal the optimizer's Newton-Euler equations.

Feet and ground: each foot is a collision sphere of radius :data:`FOOT_RADIUS` centred on
the foot point, and the floor plane lies one radius below z = 0, so the foot point
touches it exactly at z = 0, the optimizer's ground. Only the feet collide. The contact
force acts one radius below the foot point (a moment error ``FOOT_RADIUS * |F_x|``) and
the sphere rolls by ``FOOT_RADIUS`` per radian of shank rotation: both negligible.

Contact parameters (:class:`ContactSettings`), in units of the time sqrt(L/g) and the leg
length L: the friction coefficient is ``params.friction`` on a pyramidal cone (in the
plane exactly the optimizer's ``|f_x| <= mu f_z``), with no-slip iterations. ``solref``
(0.004, 1) is stiff for steps of ~0.8 time units. ``solimp`` (0.7, 0.99, 1e-4) is soft
at first touch and stiff beyond 0.1 mm-equivalent (1e-4 L) of penetration. The low
impedance at small penetration matters: MuJoCo's equilibrium penetration scales with
``(1 - d) / d``, and with the stiff (0.95, 0.99, 1e-3) the loaded stance foot's
penetration reached zero and its contact broke 5-7 knots (of 40) before heel strike,
while the optimizer's pin still carried most of the body weight; with (0.7, 0.99, 1e-4)
it held to heel strike on the nominal steps (measured under PD tracking; peak penetration
3e-5 L) and the closed-loop feedback share fell from ~18-20 % to ~12-14 %. The knee limit
(the knee-lock) uses the same time constant. The physics runs RK4 at :data:`TIMESTEP`
(nothing is damped, so RK4's accuracy pays).
"""

from __future__ import annotations

from dataclasses import dataclass

from ioc_bench.model.catalogue import model_of
from ioc_bench.model.feet import ROLLING_FEET, FootedParams
from ioc_bench.model.params import SegmentParams, WalkerParams
from ioc_bench.model.walker import WALKER

#: Radius of each foot's collision sphere (leg lengths).
FOOT_RADIUS = 0.001
#: Physics timestep in units of sqrt(L/g) (the optimizer's knots are ~0.02 apart).
TIMESTEP = 0.0005
#: Legs of the MuJoCo model; the demonstration's stance/swing roles map onto them.
LEGS: tuple[str, str] = ("a", "b")
#: Joint names in qpos (= qvel) order.
JOINTS: tuple[str, ...] = ("rootx", "rootz", "rooty", "hip_a", "knee_a", "hip_b", "knee_b")
#: Motor names in ctrl order: ``ACTUATORS`` with leg a in the stance role.
MOTORS: tuple[str, ...] = ("hip_a", "hip_b", "knee_a", "knee_b")
#: Colours of the torso and of legs a and b (RGBA).
_COLORS = {"torso": "0.2 0.2 0.2 1", "a": "0.85 0.2 0.2 1", "b": "0.2 0.35 0.85 1"}


@dataclass(frozen=True)
class ContactSettings:
    """Soft-contact, knee-limit and integration settings of the generated model.

    Attributes:
        solref: contact (timeconst, dampratio); timeconst must exceed 2 timesteps.
        solimp: contact impedance (dmin, dmax, width, midpoint, power).
        limit_solref: knee-limit (timeconst, dampratio): the knee-lock.
        noslip_iterations: post-solve iterations removing slip of sticking contacts.
        timestep: physics timestep (units of sqrt(L/g)).
    """

    solref: tuple[float, float] = (0.004, 1.0)
    solimp: tuple[float, float, float, float, float] = (0.7, 0.99, 0.0001, 0.5, 2.0)
    limit_solref: tuple[float, float] = (0.004, 1.0)
    noslip_iterations: int = 10
    timestep: float = TIMESTEP

    def __post_init__(self) -> None:
        if not self.timestep > 0:
            raise ValueError(f"timestep must be positive, got {self.timestep}")
        for name in ("solref", "limit_solref"):
            if getattr(self, name)[0] < 2 * self.timestep:
                raise ValueError(f"{name} time constant must be >= 2 timesteps ({2 * self.timestep})")


def _fmt(*values: float) -> str:
    return " ".join(f"{v:.12g}" for v in values)


def _inertial(seg: SegmentParams, com_z: float) -> str:
    """The ``<inertial>`` element of a segment: the parameters' inertia about y, thin rod otherwise."""
    inertia = _fmt(seg.inertia, seg.inertia, 1e-3 * seg.inertia)
    return f'<inertial pos="0 0 {com_z:.12g}" mass="{seg.mass:.12g}" diaginertia="{inertia}"/>'


@dataclass(frozen=True)
class FootSphere:
    """Each foot's collision sphere, in its shank's frame.

    Attributes:
        radius: the sphere's radius (leg lengths).
        lift: its centre above the shank's end, along the shank's axis.
        roll: radius of the optimizer's rolling arc at the foot (0: a point foot), whose
            centre is the sphere's: the ground contact lies ``roll`` below the site ``foot_<leg>``.
    """

    radius: float
    lift: float
    roll: float

    @property
    def floor_z(self) -> float:
        """Height of the floor plane: the sphere's lowest point with the shank vertical and
        its end at z = 0 (the optimizer's ground)."""
        return self.lift - self.radius


def foot_sphere(params: WalkerParams | FootedParams) -> FootSphere:
    """The feet of ``params``: a point foot's tiny sphere, or a rolling arc's whole sphere.

    Raises:
        ValueError: for a walker with feet that do not roll (it has no MuJoCo model).
    """
    if isinstance(params, WalkerParams):
        return FootSphere(FOOT_RADIUS, 0.0, 0.0)
    if params.feet != "roll":
        raise ValueError(f"of the walkers with feet only rolling feet have a MuJoCo model, got {params.feet!r}")
    return FootSphere(params.roll_radius, params.roll_radius, params.roll_radius)


def _foot(p: WalkerParams | FootedParams, leg: str, foot: FootSphere) -> list[str]:
    """The foot's collision sphere, its visual and its site ``foot_<leg>`` (the sphere's centre)."""
    rgba = _COLORS[leg]
    pos = f'pos="0 0 {-p.shank.length + foot.lift:.12g}"'
    # A point foot is drawn as a ball; a rolling foot as its (translucent) sphere.
    visual = f'size="0.03" rgba="{rgba}"' if foot.roll == 0 else f'size="{foot.radius:.12g}" rgba="{rgba[:-1]}0.25"'
    return [
        f'<geom name="foot_{leg}" class="foot" type="sphere" {pos} size="{foot.radius:.12g}" rgba="{rgba}"/>',
        f'<geom name="foot_{leg}_visual" class="visual" type="sphere" {pos} {visual}/>',
        f'<site name="foot_{leg}" {pos} size="0.01"/>',
    ]


def _leg(p: WalkerParams | FootedParams, leg: str, c: ContactSettings, foot: FootSphere) -> str:
    """Thigh, shank and foot of one leg, as nested bodies (indented for the torso)."""
    th, sh, rgba = p.thigh, p.shank, _COLORS[leg]
    knee_range = f'range="0 {p.knee_max_flexion:.12g}" limited="true" solreflimit="{_fmt(*c.limit_solref)}"'
    lines = [
        f'<body name="thigh_{leg}" pos="0 0 0">',
        f'  <joint name="hip_{leg}" type="hinge" axis="0 1 0" pos="0 0 0"/>',
        f"  {_inertial(th, -th.com)}",
        f'  <geom name="thigh_{leg}" class="visual" type="capsule" fromto="0 0 0 0 0 {-th.length:.12g}" '
        f'size="0.03" rgba="{rgba}"/>',
        f'  <body name="shank_{leg}" pos="0 0 {-th.length:.12g}">',
        f'    <joint name="knee_{leg}" type="hinge" axis="0 1 0" pos="0 0 0" {knee_range}/>',
        f"    {_inertial(sh, -sh.com)}",
        f'    <geom name="shank_{leg}" class="visual" type="capsule" fromto="0 0 0 0 0 {-sh.length:.12g}" '
        f'size="0.025" rgba="{rgba}"/>',
        *(f"    {line}" for line in _foot(p, leg, foot)),
        "  </body>",
        "</body>",
    ]
    return "\n".join("      " + line for line in lines)


def walker_mjcf(params: WalkerParams | None = None, contact: ContactSettings | None = None) -> str:
    """MJCF of the planar walker for ``params`` (default: ``docs/spec.md``, "Segment parameters").

    Args:
        params: the walker's parameters, the same the optimizer uses.
        contact: soft-contact settings (default :class:`ContactSettings`).

    Returns:
        The model as an XML string, for ``mujoco.MjModel.from_xml_string``.
    """
    return _mjcf("ioc_bench_planar_walker", params or WalkerParams(), contact or ContactSettings())


def rolling_feet_mjcf(params: FootedParams | None = None, contact: ContactSettings | None = None) -> str:
    """MJCF of the walker with rolling feet for ``params`` (default: ``FootedParams()``, the
    catalogue's ``rolling-feet``): the walker's bodies and joints, each foot a sphere of
    ``roll_radius`` (module docstring, "Rolling feet").

    Raises:
        ValueError: if ``params``' feet do not roll.
    """
    return _mjcf("ioc_bench_rolling_feet", params or FootedParams(), contact or ContactSettings())


#: The writer of each gait model that has a MuJoCo model, by the model's name.
_WRITERS = {WALKER.name: walker_mjcf, ROLLING_FEET.name: rolling_feet_mjcf}
#: The gait models of the catalogue that have a MuJoCo model; the others' steps (``compass``,
#: ``ankle-feet``) are verified by the optimizer only.
MJCF_MODELS: tuple[str, ...] = tuple(_WRITERS)


def check_mjcf_model(name: str) -> str:
    """``name`` if that gait model has a MuJoCo model; else ``ValueError`` in one line naming it."""
    if name not in _WRITERS:
        raise ValueError(
            f"the {name!r} gait model has no MuJoCo model: only the {' and '.join(MJCF_MODELS)} models have one so far"
        )
    return name


def model_mjcf(params: WalkerParams | FootedParams, contact: ContactSettings | None = None) -> str:
    """MJCF of the gait model ``params`` are the parameters of (:func:`~ioc_bench.model.catalogue.model_of`):
    the walker's or the rolling-feet walker's. ``ValueError`` in one line for parameters of
    no catalogue model or of a model without a MuJoCo model (naming it)."""
    return _WRITERS[check_mjcf_model(model_of(params).name)](params, contact)


def _mjcf(name: str, p: WalkerParams | FootedParams, c: ContactSettings) -> str:
    """The model's XML: options, floor, torso with two legs, motors, standing keyframe."""
    foot = foot_sphere(p)
    to, mu, tmax = p.torso, f"{p.friction:.12g}", p.max_torque
    contact_params = f'solref="{_fmt(*c.solref)}" solimp="{_fmt(*c.solimp)}" friction="{mu} 0 0" condim="3"'
    motors = "\n".join(
        f'    <motor name="{m}" joint="{m}" gear="1" ctrllimited="true" ctrlrange="{_fmt(-tmax, tmax)}"/>'
        for m in MOTORS
    )
    return f"""<mujoco model="{name}">
  <compiler angle="radian" inertiafromgeom="false" autolimits="true"/>
  <option timestep="{c.timestep:.12g}" gravity="0 0 {-p.gravity:.12g}" integrator="RK4" cone="pyramidal"
          noslip_iterations="{c.noslip_iterations}"/>
  <visual>
    <global offwidth="1280" offheight="960"/>
    <headlight ambient="0.4 0.4 0.4" diffuse="0.6 0.6 0.6"/>
  </visual>
  <default>
    <joint damping="0" armature="0" frictionloss="0"/>
    <geom contype="0" conaffinity="0"/>
    <default class="visual">
      <geom contype="0" conaffinity="0" group="1"/>
    </default>
    <default class="foot">
      <geom contype="1" conaffinity="0" group="2" {contact_params}/>
    </default>
  </default>
  <asset>
    <texture name="grid" type="2d" builtin="checker" rgb1="0.85 0.85 0.85" rgb2="0.7 0.7 0.7" width="256" height="256"/>
    <material name="grid" texture="grid" texrepeat="4 4" texuniform="true"/>
  </asset>
  <worldbody>
    <light name="light" pos="0 -2 4" dir="0 0.5 -1" directional="true"/>
    <geom name="floor" type="plane" pos="0 0 {foot.floor_z:.12g}" size="0 0 0.05" material="grid"
          contype="0" conaffinity="1" {contact_params}/>
    <body name="torso" pos="0 0 0">
      <joint name="rootx" type="slide" axis="1 0 0" pos="0 0 0"/>
      <joint name="rootz" type="slide" axis="0 0 1" pos="0 0 0"/>
      <joint name="rooty" type="hinge" axis="0 1 0" pos="0 0 0"/>
      {_inertial(to, to.com)}
      <geom name="torso" class="visual" type="capsule" fromto="0 0 0 0 0 {to.length:.12g}" size="0.04"
            rgba="{_COLORS["torso"]}"/>
      <site name="hip" pos="0 0 0" size="0.01"/>
      <camera name="track" mode="trackcom" pos="0 -3.2 -0.15" xyaxes="1 0 0 0 0 1"/>
{_leg(p, "a", c, foot)}
{_leg(p, "b", c, foot)}
    </body>
  </worldbody>
  <actuator>
{motors}
  </actuator>
  <keyframe>
    <key name="stand" qpos="0 {p.leg_length:.12g} 0 0 0 0 0"/>
  </keyframe>
</mujoco>
"""
