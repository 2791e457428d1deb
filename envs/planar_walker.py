"""``IOCBench/PlanarWalker-v0``: the ioc-bench walker as a Gymnasium environment."""

from __future__ import annotations

import os
import warnings
from typing import Any, ClassVar

import gymnasium as gym
import mujoco
import numpy as np
from gymnasium import spaces, utils

from envs.coordinates import to_generalized
from envs.physics import HealthyRange, build_model, foot_in_contact
from ioc_bench.demo import Demonstration
from ioc_bench.features import COST_FEATURES, DTAU_SCALE
from ioc_bench.model.mjcf import LEGS, ContactSettings
from ioc_bench.model.params import WalkerParams
from ioc_bench.model.walker import walker_linkage
from ioc_bench.weights import WeightSpec, parse_weights

#: Names of the reward terms in ``info``; the reward is their sum, in this order.
REWARD_TERMS: tuple[str, ...] = ("reward_forward", *(f"reward_{f}" for f in COST_FEATURES))
#: Bound of the observed velocities (clipped), as in Walker2d.
VELOCITY_BOUND = 10.0
#: Whether MuJoCo's OpenGL renderer works in this process (None: not tried yet).
_GL_AVAILABLE: bool | None = None


class PlanarWalkerEnv(gym.Env, utils.EzPickle):
    r"""
    ## Description
    The five-segment planar walker of ioc-bench (a torso, two thighs and two shanks with
    point feet; Rebula et al., "A Robustness Analysis of Inverse Optimal Control of Bipedal
    Walking") in MuJoCo. The model is generated from the same `WalkerParams` the
    trajectory optimizer uses, so a model variant (e.g. `WalkerParams().with_leg_mass_scale(1.1)`)
    is an argument, not a new environment. Everything is dimensionless: leg length 1, body
    mass 1, gravity 1, time unit $\sqrt{L/g}$. The reward is forward progress minus the
    cost features the demonstrations minimise, so an optimal demonstration is a good
    policy and an IRL method can be scored on the weights.

    Legs are physical (`a`, `b`); a demonstration's stance leg is leg `a` after
    `reset(options={"demonstration": demo})`.

    ## Action Space
    `Box(-max_torque, max_torque, (4,), float32)` (default `max_torque` 1): joint torques.

    | Num | Action                              | Min  | Max | Name (joint and motor) | Joint | Type (Unit)        |
    |-----|-------------------------------------|------|-----|------------------------|-------|--------------------|
    | 0   | Torque on the hip of leg a          | -1   | 1   | hip_a                  | hinge | torque (m g L)     |
    | 1   | Torque on the hip of leg b          | -1   | 1   | hip_b                  | hinge | torque (m g L)     |
    | 2   | Torque on the knee of leg a         | -1   | 1   | knee_a                 | hinge | torque (m g L)     |
    | 3   | Torque on the knee of leg b         | -1   | 1   | knee_b                 | hinge | torque (m g L)     |

    A joint torque acts $+\tau$ on the child segment (thigh, shank) and $-\tau$ on the
    parent. The order is ioc-bench's `ACTUATORS` (hip stance, hip swing, knee stance,
    knee swing) with leg `a` in stance.

    ## Observation Space
    `Box(low, high, (13,), float64)`; positions exclude the hip's x by default
    (`exclude_current_positions_from_observation=True`; with `False` it is prepended and
    the shape is `(14,)`). Angles in rad, lengths in leg lengths; velocities are clipped to
    $\pm 10$.

    | Num | Observation                              | Min  | Max  | Name (joint) | Joint | Type (Unit)              |
    |-----|------------------------------------------|------|------|--------------|-------|--------------------------|
    | 0   | height of the hip                        | -1   | 3    | rootz        | slide | position (L)             |
    | 1   | torso angle from vertical (+ leans fwd)  | -pi  | pi   | rooty        | hinge | angle (rad)              |
    | 2   | hip angle of leg a (thigh - torso)       | -pi  | pi   | hip_a        | hinge | angle (rad)              |
    | 3   | knee flexion of leg a (0 = straight)     | -pi  | pi   | knee_a       | hinge | angle (rad)              |
    | 4   | hip angle of leg b                       | -pi  | pi   | hip_b        | hinge | angle (rad)              |
    | 5   | knee flexion of leg b                    | -pi  | pi   | knee_b       | hinge | angle (rad)              |
    | 6   | forward velocity of the hip              | -10  | 10   | rootx        | slide | velocity (sqrt(gL))      |
    | 7   | vertical velocity of the hip             | -10  | 10   | rootz        | slide | velocity (sqrt(gL))      |
    | 8   | torso angular velocity                   | -10  | 10   | rooty        | hinge | angular velocity (1/T)   |
    | 9   | hip angular velocity of leg a            | -10  | 10   | hip_a        | hinge | angular velocity (1/T)   |
    | 10  | knee angular velocity of leg a           | -10  | 10   | knee_a       | hinge | angular velocity (1/T)   |
    | 11  | hip angular velocity of leg b            | -10  | 10   | hip_b        | hinge | angular velocity (1/T)   |
    | 12  | knee angular velocity of leg b           | -10  | 10   | knee_b       | hinge | angular velocity (1/T)   |
    | excluded | forward position of the hip         | -inf | inf  | rootx        | slide | position (L)             |

    ## Rewards
    The reward is the sum of the terms in `info` (`REWARD_TERMS`, in this order):
    - *reward_forward*: `forward_reward_weight * (x_after - x_before) / dt`, the hip's
      forward velocity over the step.
    - *reward_hip*, *reward_knee*, *reward_dtau*: minus `cost_scale * w_i` times the step's
      increment of each cost feature of ioc-bench (SPEC section 2), with `dt` as the knot
      spacing: `phi_hip = (tau_hip_a^2 + tau_hip_b^2) dt`, `phi_knee` likewise for the
      knees, `phi_dtau = 0.001 * sum_j ((tau_j - tau_j,prev) / dt)^2 dt` (0 on the first
      step after a reset). The weights `w` are unit-norm over (hip, knee, dtau).

    `info` also carries each raw increment (`phi_hip`, `phi_knee`, `phi_dtau`), the hip's
    `x_position` and `x_velocity`, and which feet touch the floor (`contact_a`, `contact_b`).

    ## Starting State
    Without options: standing with straight legs, hip at height 1 above the feet, plus
    uniform noise in $[-\epsilon, \epsilon]$ ($\epsilon$ = `reset_noise_scale`) on every joint
    angle (knee flexions take its absolute value, so they stay in range) and on every
    velocity; the walker is then lowered onto its lowest foot.
    With `options={"demonstration": demo}` (a `Demonstration` or a path to one): exactly the
    demonstration's initial state (knot 0, just after heel strike), leg `a` in stance,
    no noise. The demonstration's segment lengths must match the environment's.

    ## Episode End
    ### Termination
    The walker falls: the hip height leaves `healthy_z_range` (default `(0.6, 2.0)`) or the
    torso angle leaves `healthy_angle_range` (default `(-1, 1)` rad), when
    `terminate_when_unhealthy` is True.
    ### Truncation
    1000 steps (10 time units, about 12 walking steps) when made with `gymnasium.make`.

    ## Arguments
    `gymnasium.make("envs:IOCBench/PlanarWalker-v0", **kwargs)` (or `import envs` first).

    | Parameter                  | Type              | Default       | Description                                  |
    |----------------------------|-------------------|---------------|----------------------------------------------|
    | `params`                   | `WalkerParams`    | nominal       | the walker model (SPEC section 1)            |
    | `weights`                  | weight spec       | `"nominal"`   | set name, 3 numbers or dict; unit-normalised |
    | `forward_reward_weight`    | `float`           | `1.0`         | weight of *reward_forward*                   |
    | `cost_scale`               | `float`           | `1.0`         | multiplies every cost term                   |
    | `frame_skip`               | `int`             | `20`          | physics steps per action (dt = 0.01)         |
    | `healthy_z_range`          | `tuple`           | `(0.6, 2.0)`  | hip heights that count as standing           |
    | `healthy_angle_range`      | `tuple`           | `(-1.0, 1.0)` | torso angles that count as standing          |
    | `terminate_when_unhealthy` | `bool`            | `True`        | end the episode on a fall                    |
    | `reset_noise_scale`        | `float`           | `5e-3`        | noise of the default start                   |
    | `exclude_current_positions_from_observation` | `bool` | `True` | leave the hip's x out of the observation   |
    | `contact`                  | `ContactSettings` | default       | MuJoCo contact settings                      |
    | `render_mode`              | `str`             | `None`        | `"rgb_array"` or None                        |
    | `width`, `height`          | `int`             | `480`, `360`  | image size in pixels                         |
    | `renderer`                 | `str`             | `"auto"`      | `"mujoco"`, `"stick"` or `"auto"`, see below |

    Rendering: `"mujoco"` is MuJoCo's OpenGL renderer with a camera tracking the walker;
    headless it needs `MUJOCO_GL=egl` (or `osmesa`) set before MuJoCo is imported and the
    matching system library. `"stick"` draws a stick figure with matplotlib's Agg backend
    and always works (no OpenGL). `"auto"` tries MuJoCo once per process and falls back to
    the stick figure, silently, when no OpenGL context can be made.

    ## Version History
    * v0: initial version (MuJoCo >= 3.1, Gymnasium 1.x).
    """

    metadata: ClassVar[dict[str, Any]] = {"render_modes": ["rgb_array"], "render_fps": 100}

    def __init__(
        self,
        params: WalkerParams | None = None,
        weights: WeightSpec = "nominal",
        forward_reward_weight: float = 1.0,
        cost_scale: float = 1.0,
        frame_skip: int = 20,
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
            params,
            weights,
            forward_reward_weight,
            cost_scale,
            frame_skip,
            healthy_z_range,
            healthy_angle_range,
            terminate_when_unhealthy,
            reset_noise_scale,
            exclude_current_positions_from_observation,
            contact,
            render_mode,
            width,
            height,
            renderer,
        )
        if render_mode not in (None, *self.metadata["render_modes"]):
            raise ValueError(f"render_mode must be None or one of {self.metadata['render_modes']}, got {render_mode!r}")
        if renderer not in ("auto", "mujoco", "stick"):
            raise ValueError(f"renderer must be 'auto', 'mujoco' or 'stick', got {renderer!r}")
        if frame_skip < 1:
            raise ValueError(f"frame_skip must be >= 1, got {frame_skip}")
        self.params = params or WalkerParams()
        self.weights = parse_weights(weights)
        self.forward_reward_weight = float(forward_reward_weight)
        self.cost_scale = float(cost_scale)
        self.frame_skip = int(frame_skip)
        self.healthy = HealthyRange(tuple(healthy_z_range), tuple(healthy_angle_range))
        self.terminate_when_unhealthy = bool(terminate_when_unhealthy)
        self.reset_noise_scale = float(reset_noise_scale)
        self.exclude_x = bool(exclude_current_positions_from_observation)
        self.model = build_model(self.params, contact)
        self.data = mujoco.MjData(self.model)
        self.render_mode, self.width, self.height, self.renderer = render_mode, width, height, renderer
        self._drawer: Any = None
        self._prev_torque: np.ndarray | None = None
        self.metadata = {**self.metadata, "render_fps": int(np.round(1.0 / self.dt))}
        tmax = self.params.max_torque
        self.action_space = spaces.Box(-tmax, tmax, shape=(self.model.nu,), dtype=np.float32)
        self.observation_space = self._observation_space()

    # -- spaces and observations ----------------------------------------------------------
    @property
    def dt(self) -> float:
        """Time between actions (units of sqrt(L/g))."""
        return self.model.opt.timestep * self.frame_skip

    def _observation_space(self) -> spaces.Box:
        pos_low = [-1.0] + [-np.pi] * 5
        pos_high = [3.0] + [np.pi] * 5
        if not self.exclude_x:
            pos_low, pos_high = [-1e6, *pos_low], [1e6, *pos_high]
        low = np.array(pos_low + [-VELOCITY_BOUND] * self.model.nv)
        high = np.array(pos_high + [VELOCITY_BOUND] * self.model.nv)
        return spaces.Box(low, high, dtype=np.float64)

    def _get_obs(self) -> np.ndarray:
        qpos = self.data.qpos[1:] if self.exclude_x else self.data.qpos
        obs = np.concatenate([qpos, self.data.qvel])
        return np.clip(obs, self.observation_space.low, self.observation_space.high)

    # -- reset ----------------------------------------------------------------------------
    def reset(self, *, seed: int | None = None, options: dict[str, Any] | None = None) -> tuple[np.ndarray, dict]:
        """Start standing (with noise) or, with ``options={"demonstration": demo}``, from its knot 0."""
        super().reset(seed=seed)
        options = dict(options or {})
        unknown = set(options) - {"demonstration"}
        if unknown:
            raise ValueError(f"unknown reset option(s) {sorted(unknown)}; valid: ['demonstration']")
        mujoco.mj_resetData(self.model, self.data)
        if options.get("demonstration") is not None:
            qpos, qvel = self._demonstration_state(options["demonstration"])
        else:
            qpos, qvel = self._standing_state()
        self.data.qpos[:], self.data.qvel[:] = qpos, qvel
        mujoco.mj_forward(self.model, self.data)
        self._prev_torque = None
        return self._get_obs(), {"x_position": float(self.data.qpos[0])}

    def _demonstration_state(self, demo: Demonstration | str | os.PathLike) -> tuple[np.ndarray, np.ndarray]:
        if not isinstance(demo, Demonstration):
            demo = Demonstration.load(demo)
        lengths = [(s.length, s.com) for s in (demo.params.torso, demo.params.thigh, demo.params.shank)]
        if lengths != [(s.length, s.com) for s in (self.params.torso, self.params.thigh, self.params.shank)]:
            raise ValueError("the demonstration's segment lengths differ from this environment's walker")
        tr = demo.trajectory
        qpos, qvel, _ = to_generalized(walker_linkage(demo.params), tr.q[0], tr.v[0], None, LEGS[0])
        return qpos, qvel

    def _standing_state(self) -> tuple[np.ndarray, np.ndarray]:
        eps = self.reset_noise_scale
        qpos = np.zeros(self.model.nq)
        qpos[2:] = self.np_random.uniform(-eps, eps, size=self.model.nq - 2)
        qpos[[4, 6]] = np.abs(qpos[[4, 6]])
        qvel = self.np_random.uniform(-eps, eps, size=self.model.nv)
        self.data.qpos[:] = qpos
        mujoco.mj_kinematics(self.model, self.data)
        feet = [self.data.site_xpos[self.model.site(f"foot_{leg}").id][2] for leg in LEGS]
        qpos[1] = -min(feet)
        return qpos, qvel

    # -- step -----------------------------------------------------------------------------
    def step(self, action: np.ndarray) -> tuple[np.ndarray, float, bool, bool, dict[str, Any]]:
        tmax = self.params.max_torque
        torque = np.clip(np.asarray(action, dtype=np.float64), -tmax, tmax)
        x_before = float(self.data.qpos[0])
        self.data.ctrl[:] = torque
        mujoco.mj_step(self.model, self.data, nstep=self.frame_skip)
        x_after = float(self.data.qpos[0])
        info = self._reward_terms(torque, x_before, x_after)
        reward = float(sum(info[k] for k in REWARD_TERMS))
        self._prev_torque = torque
        fell = self.healthy.fall_reason(self.data.qpos) is not None
        terminated = bool(fell and self.terminate_when_unhealthy)
        return self._get_obs(), reward, terminated, False, info

    def _reward_terms(self, torque: np.ndarray, x_before: float, x_after: float) -> dict[str, Any]:
        """The reward terms, the raw cost-feature increments and the state summary of one step."""
        dt = self.dt
        prev = torque if self._prev_torque is None else self._prev_torque
        phi = {
            "hip": float(torque[0] ** 2 + torque[1] ** 2) * dt,
            "knee": float(torque[2] ** 2 + torque[3] ** 2) * dt,
            "dtau": DTAU_SCALE * float(np.sum(((torque - prev) / dt) ** 2)) * dt,
        }
        info: dict[str, Any] = {"reward_forward": self.forward_reward_weight * (x_after - x_before) / dt}
        for w, name in zip(self.weights, COST_FEATURES):
            info[f"reward_{name}"] = -self.cost_scale * float(w) * phi[name]
        info |= {f"phi_{name}": value for name, value in phi.items()}
        info |= {"x_position": x_after, "x_velocity": (x_after - x_before) / dt}
        info |= {f"contact_{leg}": foot_in_contact(self.model, self.data, leg) for leg in LEGS}
        return info

    # -- rendering ------------------------------------------------------------------------
    def render(self) -> np.ndarray | None:
        """An RGB image (``render_mode="rgb_array"``), from MuJoCo's renderer or a stick figure."""
        if self.render_mode is None:
            return None
        if self._drawer is None:
            self._drawer = self._make_drawer()
        if isinstance(self._drawer, mujoco.Renderer):
            self._drawer.update_scene(self.data, camera="track")
            return self._drawer.render()
        return self._drawer.render(self.data.qpos)

    def _make_drawer(self) -> Any:
        global _GL_AVAILABLE
        if self.renderer in ("mujoco", "auto") and _GL_AVAILABLE is not False:
            try:
                with warnings.catch_warnings():
                    warnings.simplefilter("ignore")  # GLFW warns before failing without a display
                    drawer = mujoco.Renderer(self.model, self.height, self.width)
                _GL_AVAILABLE = True
                return drawer
            except Exception:
                _GL_AVAILABLE = False
                if self.renderer == "mujoco":
                    raise
        from envs.drawing import StickRenderer

        return StickRenderer(self.params, self.width, self.height)

    def close(self) -> None:
        if self._drawer is not None:
            self._drawer.close()
            self._drawer = None
