"""The periodic walking-step NLP of SPEC section 2, transcribed with Hermite-Simpson.

Decision variables (named blocks, see :attr:`GaitNLP.layout`): the knot spacing ``dt`` (one
copy per knot, chained equal, so the KKT system stays banded); every segment's position
``q`` and velocity ``v`` at every knot; every pin's constraint force; the actuated and the
knee-lock torques; the pin and knee-lock impulses at heel strike. Segment accelerations
follow from Newton-Euler in closed form.

Pins hold at every knot at position, velocity and acceleration level, and Hermite-Simpson
collocates the segment angles (see :meth:`GaitNLP._collocation`). The paper's formulation
(positions at every knot, velocities at the last) leaves a parasitic mode in which pin
forces alternate between knots and midpoints; measured on this walker it let pin
velocities drift by 0.1 and pushed forces to their bounds. See ``docs/formulation.md``.

Everything that may change between solves is an NLP parameter (:attr:`GaitNLP.params`):
feature weights, task speed, the model's masses, inertias and geometry, friction, knee
range and a tracking reference. The NLP is built and differentiated once per linkage
topology and interval count; one solver serves every weight set, model variant and
projection problem. Objective::

    scale * sum_i w_i phi_i  +  sum_j r_j (x_j - xref_j)^2  +  rho * (lock complementarity)

over positions, velocities and torques ``x``; ``w = 0, r > 0`` is the IOC's projection.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Any

import casadi as ca
import numpy as np

from ioc_bench.features import ALL_FEATURES, FeatureInputs, feature_expressions
from ioc_bench.model.linkage import (
    Linkage,
    Pin,
    accelerations,
    joint_angle,
    joint_moments,
    pin_gap,
    pin_gap_acceleration,
    pin_gap_rate,
    pin_wrenches,
    point_position,
    point_velocity,
)
from ioc_bench.model.params import WalkerParams
from ioc_bench.model.walker import GaitRoles, permutation
from ioc_bench.trajopt import collocation
from ioc_bench.trajopt.layout import Constraints, Layout

#: Default number of Hermite-Simpson intervals per step (2 * 20 + 1 = 41 knots).
DEFAULT_INTERVALS = 20
#: Objective scale: features are 1e-4..1e-6, so IPOPT sees ``scale * w . phi``.
OBJECTIVE_SCALE = 100.0
#: Exact-penalty weight on the knee-lock complementarity products (all >= 0). Measured:
#: with 1 the optimum trades a lock "kick" (products ~0.01) for 75 % less cost; with 100
#: the products vanish (~1e-11) and IPOPT needs ~60 iterations; hard constraints instead
#: need 80-300.
LOCK_PENALTY = 100.0
#: Relaxed complementarity tolerance: a solution is valid only if every lock-torque x
#: flexion product is below this (torque x rad). Checked on every solve.
LOCK_TOL = 1e-6


@dataclass(frozen=True)
class Bounds:
    """Simple bounds on the decision variables (knot spacing and magnitudes)."""

    dt: tuple[float, float] = (0.004, 0.1)
    position: float = 3.0
    velocity: float = 10.0
    force: float = 20.0
    impulse: float = 5.0


class GaitNLP:
    """The walking-step NLP for one linkage topology and interval count.

    Attributes:
        layout: named blocks of the decision vector.
        params: named blocks of the parameter vector.
        constraints: named constraint groups and their bounds.
        nlp: the CasADi NLP dict ``{x, p, f, g}``.
        features_fn: ``(x, p) -> phi`` over :data:`ALL_FEATURES`.
        acc_fn: ``(x, p) -> (T*S*3,)`` segment accelerations.
        lock_fn: ``(x, p) -> complementarity products`` (zero at a valid solution).
    """

    def __init__(self, linkage: Linkage, roles: GaitRoles, n_intervals: int = DEFAULT_INTERVALS):
        if n_intervals < 2:
            raise ValueError(f"need at least 2 collocation intervals, got {n_intervals}")
        self.linkage = linkage
        self.roles = roles
        self.n_intervals = n_intervals
        self.n_knots = 2 * n_intervals + 1
        self.seg_names = tuple(s.name for s in linkage.segments)
        self.joint_names = tuple(j.name for j in linkage.joints)
        self.actuators = tuple(j.name for j in linkage.actuated)
        self.locks = tuple(j.name for j in linkage.locked)
        self.contact = linkage.pin_index(roles.contact_pin)
        self.segment_swap = permutation(self.seg_names, roles.swap_segments)
        self.lock_swap = permutation(self.locks, roles.swap_joints)
        self._declare()
        self._build()

    # -- declaration --------------------------------------------------------------------
    def _declare(self) -> None:
        t, s, p = self.n_knots, len(self.seg_names), len(self.linkage.pins)
        a, lk = len(self.actuators), len(self.locks)
        self.layout = Layout()
        for name, shape in (
            ("dt", (t,)),
            ("q", (t, s, 3)),
            ("v", (t, s, 3)),
            ("force", (t, p, 2)),
            ("tau", (t, a)),
            ("lock", (t, lk)),
            ("impulse", (p, 2)),
            ("lock_impulse", (lk,)),
        ):
            self.layout.add(name, shape)
        self.n_track = s * 6 + a
        self.params = Layout()
        for name, shape in (
            ("weights", (len(ALL_FEATURES),)),
            ("scale", (1,)),
            ("speed", (1,)),
            ("friction", (1,)),
            ("knee_max", (1,)),
            ("lock_penalty", (1,)),
            ("linkage", (len(self.linkage.parameter_vector()),)),
            ("ref", (t, self.n_track)),
            ("track", (t, self.n_track)),
        ):
            self.params.add(name, shape)

    # -- construction -------------------------------------------------------------------
    def _build(self) -> None:
        x = ca.SX.sym("x", self.layout.size)
        par = ca.SX.sym("p", self.params.size)
        var = self.layout.views(x)
        prm = self.params.views(par)
        link = self.linkage.with_parameters(list(prm["linkage"]))
        dt = var["dt"]
        step = prm["speed"][0] * (self.n_knots - 1) * dt[-1]
        acc = [self._acc(link, var, k) for k in range(self.n_knots)]
        flex = self._flexion(link, var["q"][:, :, 2])
        g = Constraints()
        g.add("uniform_dt", dt[1:] - dt[:-1])
        self._collocation(g, var, acc, dt)
        self._pins(g, link, var, acc)
        self._ground(g, link, var, prm, step)
        g.add("knee_range", [e for f in flex.ravel() for e in (f, prm["knee_max"][0] - f)], 0.0, ca.inf)
        self._impact(g, link, var, prm, step)
        lock_products = self._lock_products(var, flex)
        phi = self._features(link, var)
        track = np.concatenate(
            [var["q"].reshape(self.n_knots, -1), var["v"].reshape(self.n_knots, -1), var["tau"]], axis=1
        )
        tracking = np.sum(prm["track"] * (track - prm["ref"]) ** 2)
        objective = (
            prm["scale"][0] * ca.dot(ca.vertcat(*prm["weights"]), phi)
            + tracking
            + prm["lock_penalty"][0] * ca.sum1(lock_products)
        )
        self.constraints = g
        self.nlp = {"x": x, "p": par, "f": objective, "g": g.vector()}
        self.features_fn = ca.Function("features", [x, par], [phi])
        self.g_fn = ca.Function("g", [x, par], [g.vector()])
        self.acc_fn = ca.Function("acc", [x, par], [ca.vertcat(*[e for kn in acc for sg in kn for e in sg])])
        self.lock_fn = ca.Function("lock", [x, par], [lock_products])

    def _acc(self, link: Linkage, var: dict, k: int) -> list[list[Any]]:
        torques = {name: var["tau"][k, i] for i, name in enumerate(self.actuators)}
        for i, name in enumerate(self.locks):
            torques[name] = torques.get(name, 0) + var["lock"][k, i]
        forces = [tuple(f) for f in var["force"][k]]
        return accelerations(link, var["q"][k], forces, torques)

    def _flexion(self, link: Linkage, theta: np.ndarray) -> np.ndarray:
        """(T, L) angle of every locked joint (0 = full extension)."""
        joints = [link.joints[self.joint_names.index(n)] for n in self.locks]
        return np.array([[joint_angle(link, j, th) for j in joints] for th in theta], dtype=object)

    def _collocation(self, g: Constraints, var: dict, acc: list, dt: np.ndarray) -> None:
        """Hermite-Simpson defects of every segment's angle and angular velocity.

        A tree-shaped linkage held to the ground by one pin has the segment angles as
        independent coordinates: the pins (enforced at position, velocity and acceleration
        level at every knot, see :meth:`_pins`) fix each segment's translation from them.
        Collocating the translations as well would constrain them twice; their defects
        are the discretization error and are reported, not imposed.
        """
        for i in range(self.n_intervals):
            k = 2 * i
            h = _object_scalar(2 * dt[k])
            ys = [np.stack([var["q"][j][:, 2], var["v"][j][:, 2]], axis=1) for j in (k, k + 1, k + 2)]
            fs = [
                np.stack([var["v"][j][:, 2], np.array(acc[j], dtype=object)[:, 2]], axis=1) for j in (k, k + 1, k + 2)
            ]
            simpson, hermite = collocation.defects(*ys, *fs, h)
            g.add("collocation", list(simpson.ravel()) + list(hermite.ravel()))

    def _pins(self, g: Constraints, link: Linkage, var: dict, acc: list) -> None:
        """Pins hold at position, velocity and acceleration level at every knot.

        Acceleration-level pins make the pin forces the rigid linkage's constraint forces.
        Knot 0's positions follow from the last knot's through periodicity, so they are not
        constrained a second time.
        """
        q, v, knots = var["q"], var["v"], range(self.n_knots)
        pins = link.pins
        g.add("pin_position", [e for k in knots[1:] for pin in pins for e in pin_gap(link, pin, q[k])])
        g.add("pin_velocity", [e for k in knots for pin in pins for e in pin_gap_rate(link, pin, q[k], v[k])])
        g.add(
            "pin_acceleration",
            [e for k in knots for pin in pins for e in pin_gap_acceleration(link, pin, q[k], v[k], acc[k])],
        )

    def _ground(self, g: Constraints, link: Linkage, var: dict, prm: dict, step: Any) -> None:
        """Friction cone on the stance foot; swing foot above ground, landing one step ahead."""
        mu = prm["friction"][0]
        cone = [e for k in range(self.n_knots) for e in _cone(mu, *var["force"][k, self.contact])]
        g.add("friction", cone, 0.0, ca.inf)
        seg_name, point = self.roles.swing_foot
        i = self.seg_names.index(seg_name)
        foot = [point_position(link.segments[i], point, var["q"][k][i]) for k in range(self.n_knots)]
        g.add("swing_clearance", [z for _, z in foot[1:-1]], 0.0, ca.inf)
        g.add("landing", [foot[-1][1], foot[-1][0] - step])

    def _impact(self, g: Constraints, link: Linkage, var: dict, prm: dict, step: Any) -> None:
        """Inelastic heel strike into the relabelled initial state, shifted one step back.

        Impulse balance on every segment with the new stance foot pinned (its vertical
        impulse >= 0, inside the friction cone), knee-locks able to take impulses, and
        the old stance foot leaving the ground with zero or upward velocity.
        """
        last = self.n_knots - 1
        q_pre, v_pre = var["q"][last], var["v"][last]
        v_post = var["v"][0][self.segment_swap]  # post-impact velocities, pre-impact labels
        impact_link = _impact_linkage(link, self.roles)
        wrench = pin_wrenches(impact_link, q_pre, [tuple(f) for f in var["impulse"]])
        lock_moments = joint_moments(link, dict(zip(self.locks, var["lock_impulse"])))
        balance = []
        for i, seg in enumerate(link.segments):
            dv = v_post[i] - v_pre[i]
            balance += [seg.mass * dv[0] - wrench[i][0], seg.mass * dv[1] - wrench[i][1]]
            balance += [seg.inertia * dv[2] - wrench[i][2] - lock_moments[i]]
        g.add("impact", balance)
        g.add("impact_friction", _cone(prm["friction"][0], *var["impulse"][self.contact]), 0.0, ca.inf)
        seg_name, point = self.roles.stance_foot
        j = self.seg_names.index(seg_name)
        lift = point_velocity(link.segments[j], point, q_pre[j], v_post[j])[1]
        g.add("liftoff", [lift], 0.0, ca.inf)
        shift = np.array([step, 0, 0], dtype=object)
        g.add("periodicity", (var["q"][0][self.segment_swap] - (q_pre - shift)).ravel())

    def _lock_products(self, var: dict, flex: np.ndarray) -> ca.SX:
        """Knee-lock complementarity as products of non-negative terms (all zero when valid).

        A lock torque at knot k needs full extension at k and at the next knot, so the lock
        can stop a knee but never push it open (it adds no energy). After the last knot
        comes the post-impact motion, where the same knee carries its partner's label.
        """
        lock, lam = var["lock"], var["lock_impulse"]
        last = self.n_knots - 1
        products = []
        for i in range(len(self.locks)):
            after_impact = flex[1, self.lock_swap[i]]
            for k in range(self.n_knots):
                following = flex[k + 1, i] if k < last else after_impact
                products.append(lock[k, i] * (flex[k, i] + following))
            products.append(lam[i] * (flex[last, i] + after_impact))
        return ca.vertcat(*products)

    def _features(self, link: Linkage, var: dict) -> ca.SX:
        seg_name, point = self.roles.swing_foot
        i = self.seg_names.index(seg_name)
        foot = [point_position(link.segments[i], point, var["q"][k][i]) for k in range(self.n_knots)]
        inputs = FeatureInputs(
            dt=ca.vertcat(*var["dt"]),
            tau=ca.SX(ca.blockcat(var["tau"].tolist())),
            torso=ca.vertcat(*var["q"][:, self.seg_names.index(self.roles.torso), 2]),
            foot_z=ca.vertcat(*[z for _, z in foot]),
            step_length=foot[-1][0],
        )
        return ca.vertcat(*feature_expressions(inputs, ALL_FEATURES))

    # -- numeric inputs -----------------------------------------------------------------
    def parameter_vector(
        self,
        linkage: Linkage,
        params: WalkerParams,
        speed: float,
        weights: np.ndarray,
        ref: np.ndarray | None = None,
        track: np.ndarray | None = None,
        scale: float = OBJECTIVE_SCALE,
        lock_penalty: float = LOCK_PENALTY,
    ) -> np.ndarray:
        """The NLP parameter vector for one solve (``weights`` over :data:`ALL_FEATURES`).

        ``linkage`` must have this NLP's topology; its numbers are the model solved for.
        """
        return self.params.pack(
            {
                "weights": weights,
                "scale": scale,
                "speed": speed,
                "friction": params.friction,
                "knee_max": params.knee_max_flexion,
                "lock_penalty": lock_penalty,
                "linkage": linkage.parameter_vector(),
                "ref": 0.0 if ref is None else ref,
                "track": 0.0 if track is None else track,
            }
        )

    def variable_bounds(self, params: WalkerParams, bounds: Bounds = Bounds()) -> tuple[np.ndarray, np.ndarray]:
        """Lower and upper bounds on the decision vector."""
        mag = {
            "dt": bounds.dt,
            "q": (-bounds.position, bounds.position),
            "v": (-bounds.velocity, bounds.velocity),
            "force": (-bounds.force, bounds.force),
            "tau": (-params.max_torque, params.max_torque),
            "lock": (0.0, bounds.force),
            "impulse": (-bounds.impulse, bounds.impulse),
            "lock_impulse": (0.0, bounds.impulse),
        }
        lower = self.layout.unpack(self.layout.pack({k: lo for k, (lo, _) in mag.items()}))
        upper = self.layout.unpack(self.layout.pack({k: hi for k, (_, hi) in mag.items()}))
        # The ground can only push: vertical contact force and impulse are >= 0.
        lower["force"][:, self.contact, 1] = 0.0
        lower["impulse"][self.contact, 1] = 0.0
        return self.layout.pack(lower), self.layout.pack(upper)


def _cone(mu: Any, fx: Any, fz: Any) -> list[Any]:
    """Friction cone |fx| <= mu fz as two expressions that must be >= 0."""
    return [mu * fz - fx, mu * fz + fx]


def _impact_linkage(link: Linkage, roles: GaitRoles) -> Linkage:
    """The linkage at heel strike: the contact pin moves to the landing swing foot."""
    seg, point = roles.swing_foot
    pins = tuple(Pin(p.name, seg, point, None, (0.0, 0.0)) if p.name == roles.contact_pin else p for p in link.pins)
    return replace(link, pins=pins)


def _object_scalar(value: Any) -> np.ndarray:
    """Wrap a CasADi scalar so numpy broadcasts it elementwise over object arrays."""
    out = np.empty((), dtype=object)
    out[()] = value
    return out
