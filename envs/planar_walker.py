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
from ioc_bench.model.mjcf import LEGS, ContactSettings, check_mjcf_model
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
    """The ioc-bench walker in MuJoCo: ``gymnasium.make("envs:IOCBench/PlanarWalker-v2", **kwargs)``.

    The five-segment planar walker, its MuJoCo model generated from the same ``WalkerParams``
    as the trajectory optimizer. The reward is forward progress minus the weighted cost
    features the demonstrations minimise, so an optimal demonstration is a good policy and an
    IRL method can be scored on the weights. Feet and ground follow the optimizer's model
    (friction on the stance foot only; a heel strike only beyond the landing distance), so
    a mid-swing graze of the benchmark's steps is neither a scuff nor a heel strike.

    Actions: 4 joint torques (hips, then knees; leg a, then b) in ``[-max_torque, max_torque]``.
    Observations: 17 numbers, the positions without the hip's x (hip height, torso and joint
    angles), the velocities and the previous torque (18 with the hip's x).
    Arguments: the model (``params``), the reward's ``weights``, a ``demonstration`` every
    reset starts from, reward scales, ``frame_skip``, fall limits, noise, contact settings
    and rendering. Each is described in docs/environment.md, with the reward, ``info``,
    starting state, termination and state; the measurements are in docs/notes/.
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
        """Everything the next step depends on (docs/environment.md, "State")."""
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
        check_mjcf_model(demo.model)
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
