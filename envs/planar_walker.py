"""``IOCBench/PlanarWalker-v2``: the ioc-bench walker as a Gymnasium environment."""

from __future__ import annotations

import os
from typing import Any, ClassVar

import gymnasium as gym
import mujoco
import numpy as np
from gymnasium import spaces, utils

from envs.coordinates import to_generalized
from envs.heel_strikes import StanceTracker, landing_distance
from envs.observation import observation_names
from envs.physics import (
    DEFAULT_CONTACT,
    HealthyRange,
    MujocoParams,
    build_model,
    foot_contact_point,
    foot_geoms,
    foot_roll,
    give_feet_priority,
    set_stance_friction,
)
from envs.reference import demo_linkage
from envs.rendering import RENDERER_CHOICES, make_renderer
from envs.state import WalkerState
from ioc_bench.demo import Demonstration
from ioc_bench.features import COST_FEATURES, FEATURES, group_columns
from ioc_bench.model.catalogue import model_of
from ioc_bench.model.mjcf import LEGS, ContactSettings
from ioc_bench.model.params import WalkerParams
from ioc_bench.model.walker import ACTUATORS
from ioc_bench.weights import WeightSpec, parse_weights

#: Names of the reward terms in ``info``; the reward is their sum, in this order.
REWARD_TERMS: tuple[str, ...] = ("reward_forward", *(f"reward_{f}" for f in COST_FEATURES))
#: The weights of a standing start when the environment was made without weights.
DEFAULT_WEIGHTS = "nominal"
#: What ``get_state`` saves of MuJoCo's data: everything the next step reads.
_PHYSICS_STATE = mujoco.mjtState.mjSTATE_INTEGRATION

DemonstrationSpec = Demonstration | str | os.PathLike


class PlanarWalkerEnv(gym.Env, utils.EzPickle):
    r"""
    ## Description
    The five-segment planar walker of ioc-bench (a torso, two thighs and two shanks with
    point feet; Rebula et al., "A Robustness Analysis of Inverse Optimal Control of Bipedal
    Walking") in MuJoCo. The model is generated from the same `WalkerParams` the
    trajectory optimizer uses, so a model variant (e.g. `WalkerParams().with_leg_mass_scale(1.1)`)
    is an argument, not a new environment; so is the catalogue's `rolling-feet` walker
    (`FootedParams()`: each shank ends in a rolling arc, a MuJoCo sphere of its radius,
    and the knee is free within its range). Everything is dimensionless: leg length 1, body
    mass 1, gravity 1, time unit $\sqrt{L/g}$. The reward is forward progress minus the
    cost features the demonstrations minimise, so an optimal demonstration is a good
    policy and an IRL method can be scored on the weights.

    Physics: MuJoCo RK4 steps of 0.002 (as Walker2d-v5), 5 per action, so `dt` = 0.01;
    soft point-foot contact and the knee limit as the passive knee-lock
    (`ioc_bench.model.mjcf`). The step size was measured against 0.0005 (`ContactSettings`'
    default): docs/environment.md.

    Feet and ground follow the trajectory optimizer's model, not plain MuJoCo. There the
    ground holds the stance foot (a pin inside the friction cone) and takes the landing at
    heel strike, and never acts on the swing foot, which may touch the ground at height 0
    mid-swing with no force; the benchmark's optimal steps do (they graze the ground
    mid-swing and set the swing foot down with zero velocity). In plain MuJoCo such a
    graze is a scuff with friction (on the nominal step a braking force of 5.5 body
    weights, on the friction cone's edge, for two physics steps, unloading the stance
    foot) and was counted as a heel strike. So, unlike plain MuJoCo:
    - only the **stance** foot has friction (coefficient `params.friction`, pyramidal
      cone, MuJoCo `condim` 3); the **swing** foot's contact is frictionless (`condim` 1:
      the floor still holds it up, it cannot drag it). The feet have contact priority over
      the floor, so each foot's own `condim` decides. The two swap at every heel strike.
    - a **heel strike** is the swing foot, off the floor since the last one, touching the
      floor more than the episode's *landing distance* ahead of the stance foot:
      3/4 of the demonstration's step length when the episode started from one
      (`envs.heel_strikes.LANDING_FRACTION`), 0 (anywhere ahead) for a standing start.
      Nearer touchdowns are grazes: they are not counted and the roles stay.
    - gait events (lift-off, heel strike, and with them the friction) are checked after
      every physics step, not once per action.
    Everything else (masses, joints, knee limit, the floor's position and softness) is the
    generated model's. docs/environment.md, "Grazing swing feet", has the measurements.

    Legs are physical (`a`, `b`); a demonstration's stance leg is leg `a` after a reset
    from it. `envs.TrackingPolicy(demonstration)` turns a demonstration into actions
    (feed-forward torques plus PD tracking, legs swapped at each heel strike).

    ## Action Space
    `Box(-max_torque, max_torque, (4,), float32)` (default `max_torque` 1): joint torques.
    Actions outside the box are clipped; an action with a NaN or infinite entry, or of
    another shape, raises `ValueError`.

    | Num | Action                              | Min  | Max | Name (joint and motor) | Joint | Type (Unit)        |
    |-----|-------------------------------------|------|-----|------------------------|-------|--------------------|
    | 0   | Torque on the hip of leg a          | -1   | 1   | hip_a                  | hinge | torque (m g L)     |
    | 1   | Torque on the hip of leg b          | -1   | 1   | hip_b                  | hinge | torque (m g L)     |
    | 2   | Torque on the knee of leg a         | -1   | 1   | knee_a                 | hinge | torque (m g L)     |
    | 3   | Torque on the knee of leg b         | -1   | 1   | knee_b                 | hinge | torque (m g L)     |

    A joint torque acts $+\tau$ on the child segment (thigh, shank) and $-\tau$ on the
    parent. The order is ioc-bench's `ACTUATORS` (hip stance, hip swing, knee stance,
    knee swing) with leg `a` in stance; `info["stance_leg"]` says which leg stands now.

    ## Observation Space
    `Box(-inf, inf, (17,), float64)`: MuJoCo's positions without the hip's x, its
    velocities, and the previous torque. Nothing is clipped or wrapped (angles are
    unbounded: a hip that turned a full circle reads 2 pi more). With
    `exclude_current_positions_from_observation=False` the hip's x is prepended, shape
    `(18,)`. `envs.observation.split_observation` takes one apart. Angles in rad, lengths
    in leg lengths, velocities in $\sqrt{gL}$ and 1/T.

    | Num | Observation                              | Min  | Max  | Name (joint) | Joint | Type (Unit)              |
    |-----|------------------------------------------|------|------|--------------|-------|--------------------------|
    | 0   | height of the hip                        | -inf | inf  | rootz        | slide | position (L)             |
    | 1   | torso angle from vertical (+ leans fwd)  | -inf | inf  | rooty        | hinge | angle (rad)              |
    | 2   | hip angle of leg a (thigh - torso)       | -inf | inf  | hip_a        | hinge | angle (rad)              |
    | 3   | knee flexion of leg a (0 = straight)     | -inf | inf  | knee_a       | hinge | angle (rad)              |
    | 4   | hip angle of leg b                       | -inf | inf  | hip_b        | hinge | angle (rad)              |
    | 5   | knee flexion of leg b                    | -inf | inf  | knee_b       | hinge | angle (rad)              |
    | 6   | forward velocity of the hip              | -inf | inf  | rootx        | slide | velocity (sqrt(gL))      |
    | 7   | vertical velocity of the hip             | -inf | inf  | rootz        | slide | velocity (sqrt(gL))      |
    | 8   | torso angular velocity                   | -inf | inf  | rooty        | hinge | angular velocity (1/T)   |
    | 9   | hip angular velocity of leg a            | -inf | inf  | hip_a        | hinge | angular velocity (1/T)   |
    | 10  | knee angular velocity of leg a           | -inf | inf  | knee_a       | hinge | angular velocity (1/T)   |
    | 11  | hip angular velocity of leg b            | -inf | inf  | hip_b        | hinge | angular velocity (1/T)   |
    | 12  | knee angular velocity of leg b           | -inf | inf  | knee_b       | hinge | angular velocity (1/T)   |
    | 13  | previous torque, hip of leg a            | -1   | 1    | hip_a        | motor | torque (m g L)           |
    | 14  | previous torque, hip of leg b            | -1   | 1    | hip_b        | motor | torque (m g L)           |
    | 15  | previous torque, knee of leg a           | -1   | 1    | knee_a       | motor | torque (m g L)           |
    | 16  | previous torque, knee of leg b           | -1   | 1    | knee_b       | motor | torque (m g L)           |
    | excluded | forward position of the hip         | -inf | inf  | rootx        | slide | position (L)             |

    The previous torque is the last action as applied (clipped), 0 after a reset; it is
    observed because the *reward_dtau* term depends on it. The first step after a reset has
    *reward_dtau* = 0 whatever its torque (the torque-rate feature's sum has no term before
    the first knot).

    ## Rewards
    The reward is the sum of the terms in `info` (`REWARD_TERMS`, in this order):
    - *reward_forward*: `forward_reward_weight * (x_after - x_before) / dt`, the hip's
      forward velocity over the step.
    - *reward_hip*, *reward_knee*, *reward_dtau*: minus `cost_scale * w_i` times the step's
      increment of each cost feature of ioc-bench, computed by the very function the
      optimizer sums over a step's knots (`ioc_bench.features.FEATURES[name].increment`,
      with `dt` as the knot spacing). Like the features they are in the paper's units (SI
      units of a 1 m, 1 kg walker under g = 9.81: torques in N m, time in s):
      `phi_hip = (tau_hip_a^2 + tau_hip_b^2) dt` with `tau` in N m and `dt` in s, `phi_knee`
      likewise for the knees, `phi_dtau = 0.001 * sum_j ((tau_j - tau_j,prev) / dt)^2 dt`
      (0 on the first step after a reset). A demonstration's feature is the sum of these
      increments over its step divided by the step's duration in seconds. The weights `w`
      are unit-norm over (hip, knee, dtau): the `weights` argument if given; else those of
      the demonstration the episode started from, and nominal (1, 1, 1) for a standing start.
      `env.weights` holds the ones in use and `reset`'s `info["reward_weights"]` reports them.

    `info` also carries each raw increment (`phi_hip`, `phi_knee`, `phi_dtau`), the hip's
    `x_position` and `x_velocity`, which feet touch the floor (`contact_a`, `contact_b`),
    the leg in the stance role (`stance_leg`, "a" or "b") and the heel strikes since the
    reset (`heel_strikes`). A heel strike is the swing foot landing (see Description: it
    touches the floor beyond the landing distance ahead of the stance foot after having
    left it; checked after every physics step); the roles, and the feet's friction, then
    swap. `reset`'s `info` has `x_position`, `stance_leg`, `heel_strikes` and
    `reward_weights`.

    ## Starting State
    Without a demonstration: `init_qpos` (standing with straight legs, hip at height 1
    above the feet) and `init_qvel` (0) plus uniform noise in $[-\epsilon, \epsilon]$
    ($\epsilon$ = `reset_noise_scale`) on every joint angle (knee flexions take its absolute
    value, so they stay in range) and on every velocity; the walker is then lowered onto
    its lowest foot, whose leg is the stance leg (the other foot is frictionless); the
    landing distance is 0.
    With a demonstration (the `demonstration` argument, or `reset(options={"demonstration":
    demo})` for one reset; `options={"demonstration": None}` for a standing start):
    exactly the demonstration's initial state (knot 0, just after heel strike), leg `a` in
    stance, no noise; the landing distance is 3/4 of its step length. A `Demonstration`
    or a path to one; its segment lengths must match the environment's (masses may
    differ: that is the "wrong model" check). Vector environments reset finished episodes
    without options, so give the demonstration as an argument there
    (`gymnasium.make_vec(..., demonstration=demo)`).

    ## Episode End
    ### Termination
    The walker falls: the hip height leaves `healthy_z_range` (default `(0.6, 2.0)`) or the
    torso angle leaves `healthy_angle_range` (default `(-1, 1)` rad), when
    `terminate_when_unhealthy` is True.
    ### Truncation
    1000 steps (10 time units: 7-8 of the benchmark's steps of 1.2-1.4) when made with
    `gymnasium.make` (`max_episode_steps` overrides it).

    ## State
    `get_state()` returns a `WalkerState`: MuJoCo's integration state (time, `qpos`,
    `qvel`, the solver's warm start, controls, applied forces) and the environment's own
    (previous torque, stance leg, which also sets the feet's friction, heel-strike
    bookkeeping and landing distance, reward weights).
    `set_state(state)` restores it exactly: the next `step` gives bit-for-bit the same
    result. As in Gymnasium's `MujocoEnv`, `set_state(qpos, qvel)` sets positions and
    velocities only, and `state_vector()` is `concatenate([qpos, qvel])`. Pickling and
    `copy.deepcopy` carry the state and the random generator along.

    ## Arguments
    `gymnasium.make("envs:IOCBench/PlanarWalker-v2", **kwargs)` (or `import envs` first).

    | Parameter                  | Type              | Default       | Description                                  |
    |----------------------------|-------------------|---------------|----------------------------------------------|
    | `params`                   | `WalkerParams`    | nominal       | the model; `FootedParams`: rolling feet      |
    | `weights`                  | weight spec       | `None`        | unit-normalised; None: see Rewards           |
    | `demonstration`            | `Demonstration`, path or None | `None` | start every episode from its knot 0     |
    | `forward_reward_weight`    | `float`           | `1.0`         | weight of *reward_forward*                   |
    | `cost_scale`               | `float`           | `1.0`         | multiplies every cost term                   |
    | `frame_skip`               | `int`             | `5`           | physics steps per action (dt = 0.01)         |
    | `healthy_z_range`          | `tuple`           | `(0.6, 2.0)`  | hip heights that count as standing           |
    | `healthy_angle_range`      | `tuple`           | `(-1.0, 1.0)` | torso angles that count as standing          |
    | `terminate_when_unhealthy` | `bool`            | `True`        | end the episode on a fall                    |
    | `reset_noise_scale`        | `float`           | `5e-3`        | noise of the standing start                  |
    | `exclude_current_positions_from_observation` | `bool` | `True` | leave the hip's x out of the observation   |
    | `contact`                  | `ContactSettings` | timestep 0.002 | MuJoCo contact settings and physics timestep |
    | `render_mode`              | `str`             | `None`        | `"rgb_array"` or None                        |
    | `width`, `height`          | `int`             | `480`, `360`  | image size in pixels                         |
    | `renderer`                 | `str`             | `"auto"`      | `"mujoco"`, `"stick"` or `"auto"`, see below |

    Rendering: `"mujoco"` is MuJoCo's OpenGL renderer with a camera tracking the walker;
    headless it needs `MUJOCO_GL=egl` (or `osmesa`) set before MuJoCo is imported and the
    matching system library, and it raises `RendererUnavailableError` when no OpenGL
    context can be made. `"stick"` draws a stick figure with matplotlib's Agg backend and
    always works (no OpenGL). `"auto"` tries MuJoCo and falls back to the stick figure
    when no OpenGL context can be made (once per process). `env.renderer_in_use` says which
    one draws (`"mujoco"` or `"stick"`; None before the first `render`). With software
    OpenGL (e.g. Mesa's llvmpipe through EGL) MuJoCo's frames cost far more than the stick
    figure's: see docs/environment.md.

    ## Version History
    * v2: contact as in the trajectory optimizer's model: the swing foot is frictionless
      and the stance foot keeps the friction, swapping at heel strikes; a heel strike
      needs the touchdown to be beyond the landing distance (3/4 of the demonstration's
      step) ahead of the stance foot, so mid-swing grazes are not counted; gait events
      are checked after every physics step (v1: plain MuJoCo contact, both feet with
      friction, any touchdown ahead counted, checked once per action). The state carries
      the landing distance.
    * v1: physics steps of 0.002 with `frame_skip` 5 (v0: 0.0005 and 20; `dt` is still
      0.01), about 2.5x the steps per second; observations no longer clipped (velocities
      were clipped at +-10 and angles at +-pi) and extended by the previous torque (17
      entries); NaN or infinite actions raise;
      `info` reports the stance leg and heel strikes; `get_state`/`set_state`/
      `state_vector`/`init_qpos`, and pickling and `deepcopy` keep the state; the
      `demonstration` argument (vector autoreset); `weights=None` follows the
      demonstration's weights; `renderer="mujoco"` never falls back silently, and
      `renderer_in_use` reports the renderer.
    * v0: initial version (MuJoCo >= 3.1, Gymnasium 1.x).
    """

    metadata: ClassVar[dict[str, Any]] = {"render_modes": ["rgb_array"], "render_fps": 100}

    def __init__(
        self,
        params: MujocoParams | None = None,
        weights: WeightSpec | None = None,
        demonstration: DemonstrationSpec | None = None,
        forward_reward_weight: float = 1.0,
        cost_scale: float = 1.0,
        frame_skip: int = 5,
        healthy_z_range: tuple[float, float] = (0.6, 2.0),
        healthy_angle_range: tuple[float, float] = (-1.0, 1.0),
        terminate_when_unhealthy: bool = True,
        reset_noise_scale: float = 5e-3,
        exclude_current_positions_from_observation: bool = True,
        contact: ContactSettings | None = None,
        render_mode: str | None = None,
        width: int = 480,
        height: int = 360,
        renderer: str = "auto",
    ):
        utils.EzPickle.__init__(
            self,
            params=params,
            weights=weights,
            demonstration=demonstration,
            forward_reward_weight=forward_reward_weight,
            cost_scale=cost_scale,
            frame_skip=frame_skip,
            healthy_z_range=healthy_z_range,
            healthy_angle_range=healthy_angle_range,
            terminate_when_unhealthy=terminate_when_unhealthy,
            reset_noise_scale=reset_noise_scale,
            exclude_current_positions_from_observation=exclude_current_positions_from_observation,
            contact=contact,
            render_mode=render_mode,
            width=width,
            height=height,
            renderer=renderer,
        )
        if render_mode not in (None, *self.metadata["render_modes"]):
            raise ValueError(f"render_mode must be None or one of {self.metadata['render_modes']}, got {render_mode!r}")
        if renderer not in RENDERER_CHOICES:
            raise ValueError(f"renderer must be 'auto', 'mujoco' or 'stick', got {renderer!r}")
        if int(frame_skip) != frame_skip or frame_skip < 1:
            raise ValueError(f"frame_skip must be an integer >= 1, got {frame_skip}")
        if not (np.isfinite(reset_noise_scale) and reset_noise_scale >= 0):
            raise ValueError(f"reset_noise_scale must be a finite number >= 0, got {reset_noise_scale}")
        for name, value in (("width", width), ("height", height)):
            if int(value) != value or value < 1:
                raise ValueError(f"{name} must be a positive integer, got {value}")
        self.params = params or WalkerParams()
        self._fixed_weights = None if weights is None else parse_weights(weights)
        self.demonstration = None if demonstration is None else self._checked_demonstration(demonstration)
        self.weights = self._episode_weights(self.demonstration)
        self.forward_reward_weight = float(forward_reward_weight)
        self.cost_scale = float(cost_scale)
        self.frame_skip = int(frame_skip)
        self.healthy = HealthyRange(tuple(healthy_z_range), tuple(healthy_angle_range))
        self.terminate_when_unhealthy = bool(terminate_when_unhealthy)
        self.reset_noise_scale = float(reset_noise_scale)
        self.exclude_x = bool(exclude_current_positions_from_observation)
        self.model = build_model(self.params, contact or DEFAULT_CONTACT)
        give_feet_priority(self.model)
        self.data = mujoco.MjData(self.model)
        self.render_mode, self.width, self.height, self.renderer = render_mode, int(width), int(height), renderer
        #: The renderer drawing the frames ("mujoco" or "stick"); None before the first render.
        self.renderer_in_use: str | None = None
        self._drawer: Any = None
        self._prev_torque: np.ndarray | None = None
        self._stance = StanceTracker()
        self._feet = {leg: self.model.site(f"foot_{leg}").id for leg in LEGS}
        self._foot_roll = foot_roll(self.params)
        #: Motor columns of each actuator group (motors in ``ACTUATORS`` order, leg a in stance).
        self._groups = group_columns(model_of(self.params), ACTUATORS)
        self._foot_geoms = foot_geoms(self.model)
        self._set_friction()
        #: The noiseless standing start: straight legs, hip one leg length above the feet, at rest.
        self.init_qpos = np.array([0.0, self.params.leg_length, 0.0, 0.0, 0.0, 0.0, 0.0])
        self.init_qvel = np.zeros(self.model.nv)
        self.metadata = {**self.metadata, "render_fps": int(np.round(1.0 / self.dt))}
        tmax = self.params.max_torque
        self.action_space = spaces.Box(-tmax, tmax, shape=(self.model.nu,), dtype=np.float32)
        size = len(observation_names(self.exclude_x))
        self.observation_space = spaces.Box(-np.inf, np.inf, shape=(size,), dtype=np.float64)

    # -- observations and state -----------------------------------------------------------
    @property
    def dt(self) -> float:
        """Time between actions (units of sqrt(L/g))."""
        return self.model.opt.timestep * self.frame_skip

    def _get_obs(self) -> np.ndarray:
        qpos = self.data.qpos[1:] if self.exclude_x else self.data.qpos
        prev = np.zeros(self.model.nu) if self._prev_torque is None else self._prev_torque
        return np.concatenate([qpos, self.data.qvel, prev])

    def state_vector(self) -> np.ndarray:
        """``concatenate([qpos, qvel])``, as Gymnasium's ``MujocoEnv.state_vector``."""
        return np.concatenate([self.data.qpos, self.data.qvel])

    def get_state(self) -> WalkerState:
        """Everything the next step depends on (see the class docstring, section State)."""
        physics = np.empty(mujoco.mj_stateSize(self.model, _PHYSICS_STATE))
        mujoco.mj_getState(self.model, self.data, physics, _PHYSICS_STATE)
        return WalkerState(
            physics=physics,
            previous_torque=None if self._prev_torque is None else self._prev_torque.copy(),
            stance_leg=self._stance.stance_leg,
            swing_lifted=self._stance.swing_lifted,
            heel_strikes=self._stance.heel_strikes,
            weights=self.weights.copy(),
            landing_distance=self._stance.landing_distance,
        )

    def set_state(self, state: WalkerState | np.ndarray, qvel: np.ndarray | None = None) -> None:
        """Restore a :meth:`get_state` snapshot exactly, or (``set_state(qpos, qvel)``) set positions and velocities.

        The two-argument form is Gymnasium's ``MujocoEnv.set_state``: it leaves time, the
        previous torque and the gait bookkeeping as they are.

        Raises:
            ValueError: on a snapshot of another model, or qpos/qvel of the wrong shape or not finite.
        """
        if qvel is not None:
            qpos, qvel = np.asarray(state, dtype=float), np.asarray(qvel, dtype=float)
            if qpos.shape != (self.model.nq,) or qvel.shape != (self.model.nv,):
                raise ValueError(f"qpos and qvel must have shapes ({self.model.nq},), got {qpos.shape}, {qvel.shape}")
            if not (np.all(np.isfinite(qpos)) and np.all(np.isfinite(qvel))):
                raise ValueError("qpos and qvel must be finite")
            self.data.qpos[:], self.data.qvel[:] = qpos, qvel
            mujoco.mj_forward(self.model, self.data)
            return
        if not isinstance(state, WalkerState):
            raise ValueError(f"set_state takes a WalkerState from get_state(), or (qpos, qvel); got {type(state)}")
        size = mujoco.mj_stateSize(self.model, _PHYSICS_STATE)
        if state.physics.shape != (size,):
            raise ValueError(f"the snapshot's physics state has {state.physics.shape[0]} numbers, this model's {size}")
        self._stance = StanceTracker(state.stance_leg, state.swing_lifted, state.heel_strikes, state.landing_distance)
        self._set_friction()
        mujoco.mj_setState(self.model, self.data, np.array(state.physics), _PHYSICS_STATE)
        mujoco.mj_forward(self.model, self.data)
        self._prev_torque = None if state.previous_torque is None else np.array(state.previous_torque)
        self.weights = np.array(state.weights)

    def __getstate__(self) -> dict[str, Any]:
        """The constructor's arguments (``EzPickle``) plus the state and the random generator."""
        return utils.EzPickle.__getstate__(self) | {
            "walker_state": self.get_state(),
            "np_random": self._np_random,
            "np_random_seed": self._np_random_seed,
        }

    def __setstate__(self, d: dict[str, Any]) -> None:
        utils.EzPickle.__setstate__(self, d)
        self.set_state(d["walker_state"])
        self._np_random, self._np_random_seed = d["np_random"], d["np_random_seed"]

    # -- reset ----------------------------------------------------------------------------
    def reset(self, *, seed: int | None = None, options: dict[str, Any] | None = None) -> tuple[np.ndarray, dict]:
        """Start standing (with noise) or from a demonstration's knot 0 (argument or ``options``)."""
        super().reset(seed=seed)
        options = dict(options or {})
        unknown = set(options) - {"demonstration"}
        if unknown:
            raise ValueError(f"unknown reset option(s) {sorted(unknown)}; valid: ['demonstration']")
        demo = self.demonstration
        if "demonstration" in options:
            demo = None if options["demonstration"] is None else self._checked_demonstration(options["demonstration"])
        mujoco.mj_resetData(self.model, self.data)
        if demo is not None:
            qpos, qvel = self._demonstration_state(demo)
            stance = LEGS[0]
        else:
            qpos, qvel, stance = self._standing_state()
        self._stance = StanceTracker(stance, landing_distance=landing_distance(demo))
        self._set_friction()
        self.data.qpos[:], self.data.qvel[:] = qpos, qvel
        mujoco.mj_forward(self.model, self.data)
        self._prev_torque = None
        self.weights = self._episode_weights(demo)
        info = {
            "x_position": float(self.data.qpos[0]),
            "stance_leg": stance,
            "heel_strikes": 0,
            "reward_weights": self.weights.copy(),
        }
        return self._get_obs(), info

    def _episode_weights(self, demo: Demonstration | None) -> np.ndarray:
        if self._fixed_weights is not None:
            return self._fixed_weights.copy()
        return parse_weights(DEFAULT_WEIGHTS if demo is None else demo.weight_vector)

    def _checked_demonstration(self, demo: DemonstrationSpec) -> Demonstration:
        if not isinstance(demo, Demonstration):
            demo = Demonstration.load(demo)
        if model_of(demo.params) is not model_of(self.params):
            raise ValueError(f"the demonstration is of the {demo.model!r} model, not this environment's")
        lengths = [(s.length, s.com) for s in (demo.params.torso, demo.params.thigh, demo.params.shank)]
        if lengths != [(s.length, s.com) for s in (self.params.torso, self.params.thigh, self.params.shank)]:
            raise ValueError("the demonstration's segment lengths differ from this environment's walker")
        return demo

    def _demonstration_state(self, demo: Demonstration) -> tuple[np.ndarray, np.ndarray]:
        tr = demo.trajectory
        qpos, qvel, _ = to_generalized(demo_linkage(demo), tr.q[0], tr.v[0], None, LEGS[0])
        return qpos, qvel

    def _standing_state(self) -> tuple[np.ndarray, np.ndarray, str]:
        """A noisy standing pose on the floor, and the leg of its lowest foot (the stance leg)."""
        eps = self.reset_noise_scale
        qpos = self.init_qpos.copy()
        qpos[2:] += self.np_random.uniform(-eps, eps, size=self.model.nq - 2)
        qpos[[4, 6]] = np.abs(qpos[[4, 6]])
        qvel = self.init_qvel + self.np_random.uniform(-eps, eps, size=self.model.nv)
        self.data.qpos[:] = qpos
        self.data.qpos[1] = 0.0
        mujoco.mj_kinematics(self.model, self.data)
        feet = [foot_contact_point(self.model, self.data, leg, self._foot_roll)[2] for leg in LEGS]
        qpos[1] = -min(feet)
        return qpos, qvel, LEGS[int(np.argmin(feet))]

    # -- step -----------------------------------------------------------------------------
    def step(self, action: np.ndarray) -> tuple[np.ndarray, float, bool, bool, dict[str, Any]]:
        torque = self._checked_torque(action)
        x_before = float(self.data.qpos[0])
        self.data.ctrl[:] = torque
        for _ in range(self.frame_skip):
            mujoco.mj_step(self.model, self.data)
            self._gait_events()
        x_after = float(self.data.qpos[0])
        info = self._reward_terms(torque, x_before, x_after)
        reward = float(sum(info[k] for k in REWARD_TERMS))
        self._prev_torque = torque
        info["stance_leg"], info["heel_strikes"] = self._stance.stance_leg, self._stance.heel_strikes
        fell = self.healthy.fall_reason(self.data.qpos) is not None
        terminated = bool(fell and self.terminate_when_unhealthy)
        return self._get_obs(), reward, terminated, False, info

    def _feet_in_contact(self) -> dict[str, bool]:
        """Leg -> whether its foot touches the floor (MuJoCo's contacts of the last physics step)."""
        geoms = self.data.contact.geom[: self.data.ncon].ravel().tolist()  # a few ints: faster than numpy
        return {leg: gid in geoms for leg, gid in self._foot_geoms.items()}

    def _gait_events(self) -> None:
        """After each physics step: lift-off and landing of the swing foot; friction follows the roles."""
        foot_x = {leg: float(self.data.site_xpos[site, 0]) for leg, site in self._feet.items()}
        if self._stance.update(self._feet_in_contact(), foot_x):
            self._set_friction()

    def _set_friction(self) -> None:
        """Friction on the stance foot, a frictionless swing foot (``envs.physics``)."""
        set_stance_friction(self.model, self._stance.stance_leg)

    def _checked_torque(self, action: np.ndarray) -> np.ndarray:
        """The action as float64 motor torques, clipped to the bound; ValueError if malformed."""
        torque = np.asarray(action, dtype=np.float64)
        if torque.shape != (self.model.nu,):
            raise ValueError(f"action must have shape ({self.model.nu},), got {torque.shape}")
        if not np.all(np.isfinite(torque)):
            raise ValueError(f"action must be finite, got {torque.tolist()}")
        tmax = self.params.max_torque
        return np.clip(torque, -tmax, tmax)

    def _reward_terms(self, torque: np.ndarray, x_before: float, x_after: float) -> dict[str, Any]:
        """The reward terms, the raw cost-feature increments and the state summary of one step."""
        dt = self.dt
        prev = torque if self._prev_torque is None else self._prev_torque
        phi = {name: float(FEATURES[name].increment(torque, prev, dt, self._groups)) for name in COST_FEATURES}
        info: dict[str, Any] = {"reward_forward": self.forward_reward_weight * (x_after - x_before) / dt}
        for w, name in zip(self.weights, COST_FEATURES):
            info[f"reward_{name}"] = -self.cost_scale * float(w) * phi[name]
        info |= {f"phi_{name}": value for name, value in phi.items()}
        info |= {"x_position": x_after, "x_velocity": (x_after - x_before) / dt}
        info |= {f"contact_{leg}": touching for leg, touching in self._feet_in_contact().items()}
        return info

    # -- rendering ------------------------------------------------------------------------
    def render(self) -> np.ndarray | None:
        """An RGB image (``render_mode="rgb_array"``), from MuJoCo's renderer or a stick figure."""
        if self.render_mode is None:
            return None
        if self._drawer is None:
            self._drawer, self.renderer_in_use = make_renderer(
                self.renderer, self.model, self.params, self.width, self.height
            )
        if self.renderer_in_use == "mujoco":
            self._drawer.update_scene(self.data, camera="track")
            return self._drawer.render()
        return self._drawer.render(self.data.qpos)

    def close(self) -> None:
        if self._drawer is not None:
            self._drawer.close()
            self._drawer = None
