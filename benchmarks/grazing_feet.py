"""Grazing swing feet: what each contact option does to the replay of the eight demonstrations.

The benchmark's optimal steps let the swing foot touch the ground at height 0 mid-swing
(the optimizer's model puts no force on the swing foot) and set it down with zero
velocity at the step's end. This script measures, for each demonstration:

- the demonstration: its mid-swing clearance, and where its swing foot touches the ground
  (knots of height below 1e-6 leg lengths, as a fraction of the step length ahead of the
  stance foot);
- the first graze of the closed-loop walk under plain MuJoCo contact and under v2's: the
  swing foot's peak normal and friction force, how long it touched, and the least the
  stance foot carried meanwhile (body weights);
- the open loop (the demonstration's torques alone): the final-state error;
- the closed-loop check (``closed_loop_replay``, 10 steps, control every 0.002) for each
  option below: steps walked, feedback share, tracking RMS, share of control steps ending
  with the stance foot down, grazes, mean step duration over the demonstration's.

Options (environment contact x policy), each made here by subclassing for the measurement:

- ``v1``: plain MuJoCo contact (both feet with friction), any touchdown ahead of the
  stance foot is a heel strike, the policy holds the last knot until the env swaps legs;
- ``v1+next``: the same with v2's policy (the next step is tracked once the hip passes
  the step's end);
- ``zone``: both feet with friction, the landing zone (3/4 of the step) and v2's policy;
- ``frictionless``: frictionless swing foot, any touchdown ahead a heel strike, v2's policy;
- ``v2-hold``: v2's contact (frictionless swing foot, landing zone), v1's policy;
- ``v2``: the environment as it is (frictionless swing foot, landing zone, v2's policy);
- ``v2-trail``: v2, but the trailing foot keeps its friction until it leaves the floor
  (the optimizer lets it take a frictional impulse in the impact);
- ``no-swing-contact``: the optimizer's model taken literally: the swing foot does not
  collide at all until it is in the landing zone (a reference, not an environment).

Usage::

    python benchmarks/grazing_feet.py /tmp/demos8/*.npz
    python benchmarks/grazing_feet.py a.npz --options v1,v2
"""

from __future__ import annotations

import argparse
import contextlib
import sys
from collections.abc import Iterator
from pathlib import Path

import mujoco
import numpy as np

import envs.checks.closed_loop as closed_loop
import envs.planar_walker as planar_walker
from envs.checks import closed_loop_replay, open_loop_replay
from envs.coordinates import other_leg
from envs.heel_strikes import step_length
from envs.physics import STANCE_CONDIM, SWING_CONDIM
from envs.tracking import TrackingPolicy
from ioc_bench import Demonstration
from ioc_bench.model.walker import WALKER_ROLES, walker_linkage

Env = planar_walker.PlanarWalkerEnv


class PlainFriction(Env):
    """Both feet with friction, as the generated model (v1)."""

    def _set_friction(self) -> None:
        for gid in self._foot_geoms.values():
            self.model.geom_condim[gid] = STANCE_CONDIM


class AnyTouchdownAhead(Env):
    """Landing distance 0 whatever the start: any touchdown ahead of the stance foot is a heel strike (v1)."""

    def reset(self, **kwargs):
        out = super().reset(**kwargs)
        self._stance.landing_distance = 0.0
        return out


class V1(PlainFriction, AnyTouchdownAhead):
    pass


class TrailFriction(Env):
    """v2, but the trailing foot keeps its friction until it has left the floor."""

    def _gait_events(self) -> None:
        super()._gait_events()
        self._set_friction()

    def _set_friction(self) -> None:
        stance = self._stance.stance_leg
        for leg, gid in self._foot_geoms.items():
            grip = leg == stance or not self._stance.swing_lifted
            self.model.geom_condim[gid] = STANCE_CONDIM if grip else SWING_CONDIM


class NoSwingContact(Env):
    """The swing foot collides only once it is in the landing zone (or before it lifted off)."""

    def _gait_events(self) -> None:
        super()._gait_events()
        self._set_friction()

    def _set_friction(self) -> None:
        super()._set_friction()
        stance = self._stance.stance_leg
        swing = other_leg(stance)
        x = {leg: float(self.data.site_xpos[site][0]) for leg, site in self._feet.items()}
        near = x[swing] - x[stance] > self._stance.landing_distance
        collide = near or not self._stance.swing_lifted
        self.model.geom_contype[self._foot_geoms[swing]] = 1 if collide else 0
        self.model.geom_contype[self._foot_geoms[stance]] = 1


class HoldLastKnot(TrackingPolicy):
    """v1's policy: the environment's stance leg, the last knot held until it swaps."""

    def tracked_stance(self, state, stance):
        return stance


OPTIONS = {
    "v1": (V1, HoldLastKnot),
    "v1+next": (V1, TrackingPolicy),
    "zone": (PlainFriction, TrackingPolicy),
    "frictionless": (AnyTouchdownAhead, TrackingPolicy),
    "v2-hold": (Env, HoldLastKnot),
    "v2": (Env, TrackingPolicy),
    "v2-trail": (TrailFriction, TrackingPolicy),
    "no-swing-contact": (NoSwingContact, TrackingPolicy),
}


@contextlib.contextmanager
def option(name: str) -> Iterator[None]:
    """Make the checks build this option's environment and policy (measurement only)."""
    env_cls, policy_cls = OPTIONS[name]
    saved = planar_walker.PlanarWalkerEnv, closed_loop.TrackingPolicy
    planar_walker.PlanarWalkerEnv, closed_loop.TrackingPolicy = env_cls, policy_cls
    try:
        yield
    finally:
        planar_walker.PlanarWalkerEnv, closed_loop.TrackingPolicy = saved


def touches(demo: Demonstration) -> list[float]:
    """Where the demonstration's swing foot touches the ground mid-swing (fraction of the step ahead)."""
    link = walker_linkage(demo.params)
    swing = demo.trajectory.point(link, *WALKER_ROLES.swing_foot)
    stance = demo.trajectory.point(link, *WALKER_ROLES.stance_foot)
    length = step_length(demo)
    knots = np.flatnonzero(swing[1:-1, 1] < 1e-6) + 1
    return [float((swing[k, 0] - stance[k, 0]) / length) for k in knots]


def _forces(env: Env, leg: str) -> tuple[float, float]:
    """Normal and friction force of leg ``leg``'s foot on the floor (body weights, mg = 1)."""
    gid, f, normal, friction = env._foot_geoms[leg], np.zeros(6), 0.0, 0.0
    for i in range(env.data.ncon):
        if gid in env.data.contact[i].geom:
            mujoco.mj_contactForce(env.model, env.data, i, f)
            normal, friction = normal + f[0], friction + float(np.hypot(f[1], f[2]))
    return normal, friction


def first_graze(demo: Demonstration, name: str) -> dict[str, float] | None:
    """The first step's first mid-swing touchdown in the closed loop (leg b's foot; forces after a forward pass)."""
    env_cls, policy_cls = OPTIONS[name]
    env, policy = env_cls(demonstration=demo, frame_skip=1), policy_cls(demo)
    obs, info = env.reset()
    rows, end = [], 0.9 * demo.trajectory.duration
    while env.data.time < end:
        obs, _, terminated, _, info = env.step(policy(obs, info))
        mujoco.mj_forward(env.model, env.data)
        if info["contact_b"] and env.data.time > 0.1 * demo.trajectory.duration:
            rows.append((*_forces(env, "b"), _forces(env, "a")[0]))
        elif rows or terminated:
            break
    if not rows:
        return None
    a = np.array(rows)
    return {
        "normal": float(a[:, 0].max()),
        "friction": float(a[:, 1].max()),
        "duration": len(a) * env.dt,
        "stance_min": float(a[:, 2].min()),
    }


def knee_limit_power(env: Env, leg: str) -> float:
    """Power of the knee limit's constraint force on leg ``leg`` (constraint force times velocity)."""
    mujoco.mj_forward(env.model, env.data)
    joint = env.model.joint(f"knee_{leg}").id
    rows = (env.data.efc_type == mujoco.mjtConstraint.mjCNSTR_LIMIT_JOINT) & (env.data.efc_id == joint)
    return float(np.dot(env.data.efc_force[rows], env.data.efc_vel[rows]))


def energy_losses(demo: Demonstration, steps: int = 6) -> list[tuple[float, float, float, float]]:
    """v2's closed loop: per step, the energy lost (motor work minus the gain of kinetic plus
    potential energy), the part of it lost in the first 0.1 time units after the heel
    strike, the work of the swing knee's limit, and the step's duration over the
    demonstration's. The optimal step loses none."""
    env, policy = Env(demonstration=demo, frame_skip=1), TrackingPolicy(demo)
    model, data = env.model, env.data
    dofs = [model.jnt_dofadr[model.actuator_trnid[i, 0]] for i in range(model.nu)]

    def energy() -> float:
        mujoco.mj_energyPos(model, data)
        mujoco.mj_energyVel(model, data)
        return float(data.energy.sum())

    obs, info = env.reset()
    out, start, lost, early, knee, before = [], 0.0, 0.0, 0.0, 0.0, energy()
    while len(out) < steps and data.time < 3 * steps * demo.trajectory.duration:
        qvel, swing = data.qvel[dofs].copy(), other_leg(info["stance_leg"])
        obs, _, terminated, _, info = env.step(policy(obs, info))
        work = float(np.dot(data.ctrl, 0.5 * (qvel + data.qvel[dofs]))) * env.dt
        after = energy()
        loss, before = work - (after - before), after
        lost += loss
        early += loss if data.time - start <= 0.1 else 0.0
        knee += knee_limit_power(env, swing) * env.dt
        if terminated:
            break
        if info["heel_strikes"] > len(out):
            out.append((lost, early, knee, (data.time - start) / demo.trajectory.duration))
            start, lost, early, knee = float(data.time), 0.0, 0.0, 0.0
    return out


def touchdowns(demo: Demonstration, steps: int = 10) -> tuple[list[float], list[float]]:
    """v2's closed loop (control every physics step): where each touchdown of the swing
    foot began, as a fraction of the step ahead of the stance foot, for the grazes and
    for the landings (the touchdowns that ended as heel strikes)."""
    env, policy, length = Env(demonstration=demo, frame_skip=1), TrackingPolicy(demo), step_length(demo)
    obs, info = env.reset()
    grazes, landings, began, lifted = [], [], None, False
    while info["heel_strikes"] < steps and env.data.time < 3 * steps * demo.trajectory.duration:
        stance = info["stance_leg"]
        swing = other_leg(stance)
        obs, _, terminated, _, info = env.step(policy(obs, info))
        if terminated:
            break
        x = {leg: float(env.data.site_xpos[site, 0]) for leg, site in env._feet.items()}
        struck = info["stance_leg"] != stance
        if (info[f"contact_{swing}"] or struck) and lifted and began is None:
            began = (x[swing] - x[stance]) / length
        if struck:
            landings += [] if began is None else [began]
            began, lifted = None, False
        elif not info[f"contact_{swing}"]:
            grazes += [] if began is None else [began]
            began, lifted = None, True
    return grazes, landings


def closed(demo: Demonstration, name: str) -> dict[str, float]:
    with option(name):
        cl = closed_loop_replay(demo, steps=10)
    durations = np.diff((0.0, *cl.heel_strikes))
    return {
        "steps": cl.steps_walked,
        "share": cl.feedback_share,
        "rms": cl.tracking_rms,
        "stance": cl.stance_contact,
        "grazes": cl.grazes,
        "duration": float(durations.mean() / demo.trajectory.duration) if len(durations) else float("nan"),
        "last": float(durations[-1] / demo.trajectory.duration) if len(durations) else float("nan"),
    }


def tables(demos: dict[str, Demonstration], names: list[str]) -> None:
    """The demonstrations' grazes and open loops, and the closed loop of every option."""
    print(
        "demonstration        | mid-swing clearance | touches (x / step) | first graze, v1: normal, friction, "
        "duration, stance min | v2: normal, friction, duration, stance min | open loop v1, v2"
    )
    for key, demo in demos.items():
        grazes = {n: first_graze(demo, n) for n in ("v1", "v2")}
        with option("v1"):
            ol_v1 = open_loop_replay(demo).final_position_error
        ol_v2 = open_loop_replay(demo).final_position_error
        cells = []
        for g in grazes.values():
            cells.append(
                "-"
                if g is None
                else f"{g['normal']:.2f}, {g['friction']:.2f}, {g['duration']:.3f}, {g['stance_min']:.2f}"
            )
        where = ", ".join(f"{x:.2f}" for x in touches(demo)) or "-"
        print(
            f"{key:20s} | {demo.gait.mid_swing_clearance:.1e} | {where} | {cells[0]} | {cells[1]} | "
            f"{ol_v1:.2e}, {ol_v2:.2e}",
            flush=True,
        )

    print(
        "\noption           | demonstration        | steps | share | RMS     | stance down | grazes | "
        "step / demo's (mean, last)"
    )
    summary = {}
    for name in names:
        rows = {}
        for key, demo in demos.items():
            r = rows[key] = closed(demo, name)
            print(
                f"{name:16s} | {key:20s} | {r['steps']:5d} | {r['share']:.3f} | {r['rms']:.1e} | "
                f"{r['stance']:.3f}       | {r['grazes']:6d} | {r['duration']:.2f}, {r['last']:.2f}",
                flush=True,
            )
        summary[name] = rows
    print("\noption           | walk 10 steps | share < 0.2 | share median [min, max] | stance down min")
    for name, rows in summary.items():
        share = np.array([r["share"] for r in rows.values()])
        print(
            f"{name:16s} | {sum(r['steps'] >= 10 for r in rows.values())}/{len(rows)}           | "
            f"{int(np.sum(share < 0.2))}/{len(rows)}         | {np.median(share):.3f} [{share.min():.3f}, "
            f"{share.max():.3f}]    | {min(r['stance'] for r in rows.values()):.3f}"
        )


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("demos", nargs="+", type=Path, help="demonstration files")
    parser.add_argument("--options", default=",".join(OPTIONS), help="options to compare, comma-separated")
    parser.add_argument("--energy-only", action="store_true", help="only v2's energy and touchdown tables")
    args = parser.parse_args(argv)
    names = args.options.split(",")
    for name in names:
        if name not in OPTIONS:
            parser.error(f"unknown option {name!r}; valid: {', '.join(OPTIONS)}")
    demos = {p.stem: Demonstration.load(p) for p in args.demos}

    if not args.energy_only:
        tables(demos, names)
    print(
        "\nv2, energy lost per step (m g L) [of which in the first 0.1 after the heel strike] "
        "{work of the swing knee's limit} (step / demo's)"
    )
    for key, demo in demos.items():
        cells = [f"{lost:.1e} [{early:.1e}] {{{k:.1e}}} ({r:.2f})" for lost, early, k, r in energy_losses(demo)]
        print(f"{key:20s} | " + " | ".join(cells), flush=True)
    print("\nv2, touchdowns of the swing foot: where they began (x / step), grazes and landings")
    for key, demo in demos.items():
        grazes, landings = touchdowns(demo)
        span = f"{min(grazes):.2f} to {max(grazes):.2f} ({len(grazes)})" if grazes else "none"
        print(f"{key:20s} | grazes {span} | landings " + ", ".join(f"{x:.2f}" for x in sorted(landings)), flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
