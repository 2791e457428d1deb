"""The walking problem (``docs/spec.md``, "The step"): one periodic step of a gait model, as an NLP.

What is optimized and constrained lives here; how time is discretized lives in
:class:`~ioc_bench.trajopt.transcription.HermiteSimpson`. Decision variables (named blocks,
see :attr:`StepProblem.layout`): the knot spacing (the transcription's); every segment's
position ``q`` and velocity ``v`` at every knot; every pin's constraint force; the actuated
and the locked-joint torques; the pin, trailing-foot and lock impulses at heel strike.
Segment accelerations follow from Newton-Euler in closed form.

Pins hold at every knot at position, velocity and acceleration level, and the segment
angles are the collocated states (see :meth:`StepProblem._dynamics`). The paper's
formulation (positions at every knot, velocities at the last) leaves a parasitic mode in
which pin forces alternate between knots and midpoints; measured on the walker it let pin
velocities drift by 0.1 and pushed forces to their bounds (``docs/formulation.md``).

Everything that may change between solves is an NLP parameter (:attr:`StepProblem.params`):
feature weights, task speed, the model's masses, inertias and geometry, friction, lock
range and a tracking reference; the task's step length and the lift-off rule are
per-solve bounds. The NLP is built and differentiated once per model and interval count;
one solver serves every weight set, model variant and projection problem. Objective::

    scale * sum_i w_i phi_i  +  sum_j r_j (x_j - xref_j)^2  +  s * |second differences of tau|^2
    +  rho * (lock complementarity)

over positions, velocities and torques ``x``; ``w = 0, r > 0`` is the IOC's projection, and
``s > 0`` smooths it (a torque-curvature term that is no cost feature: see
:mod:`ioc_bench.ioc.smoothing`).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, replace
from functools import cached_property
from typing import Any

import casadi as ca
import numpy as np

from ioc_bench.features import check_model_names, feature_vector, model_features, step_inputs
from ioc_bench.model.gait_model import GaitModel, GaitParams, GaitRoles, permutation
from ioc_bench.model.linkage import (
    Linkage,
    Pin,
    accelerations,
    ground_gap,
    ground_gap_rate,
    joint_angle,
    joint_moments,
    pin_gap,
    pin_gap_acceleration,
    pin_gap_rate,
    pin_wrenches,
)
from ioc_bench.trajopt.layout import Constraints, Layout
from ioc_bench.trajopt.transcription import HermiteSimpson

#: Default number of Hermite-Simpson intervals per step (2 * 20 + 1 = 41 knots).
DEFAULT_INTERVALS = 20
#: Objective scale: IPOPT sees ``scale * w . phi`` (about 0.05 at the nominal optimum).
OBJECTIVE_SCALE = 0.25
#: Exact-penalty weight on the knee-lock complementarity products (all >= 0). Measured:
#: with 1 the optimum trades a lock "kick" (products ~0.01) for 75 % less cost; with 100
#: the products vanish (~1e-11) and IPOPT needs ~60 iterations; hard constraints instead
#: need 80-300.
LOCK_PENALTY = 100.0
#: Relaxed complementarity tolerance: a solution is valid only if every lock-torque x
#: flexion product is below this (torque x rad). Checked on every solve.
LOCK_TOL = 1e-6
#: Flexion offset inside the lock products. IPOPT relaxes bounds by 1e-8, so a flexion may
#: reach -1e-8; a product with a bare flexion could then turn negative, and the penalty
#: rewarded hyperextending locked knees by 1e-8 rad (measured: 2e-5 of objective at a
#: demonstration, which a projection traded for a 1e-8 tracking error). With the offset
#: every product is >= 0 on the relaxed feasible set.
LOCK_SLACK = 1e-8


#: Active inequalities that are physics: the ground's contact (a foot unloading, the friction
#: cone's edge, the swing foot touching the ground), joint limits (a knee at full extension
#: or at its flexion limit) and torque limits. Keys as :meth:`ForwardProblem.active_bounds` gives.
PHYSICAL_BOUNDS = frozenset(
    {
        "friction",
        "impact_friction",
        "trail_friction",
        "swing_clearance",
        "knee_range",
        "joint_range",
        "bound:force:zero",
        "bound:impulse:zero",
        "bound:tau:lower",
        "bound:tau:upper",
    }
)
#: Bounds that only say a passive element is idle: a lock, a lock impulse or the trailing
#: foot's impulse at zero.
IDLE_BOUNDS = frozenset({"bound:lock:zero", "bound:lock_impulse:zero", "bound:trail_impulse:zero"})


def classify_active(active: dict[str, int]) -> dict[str, dict[str, int]]:
    """Split active bounds into ``physical``, ``idle`` and ``artificial`` ones (the last are
    the transcription's own limits, e.g. the knot spacing, or a relaxed formulation's)."""
    out: dict[str, dict[str, int]] = {"physical": {}, "idle": {}, "artificial": {}}
    for key, count in active.items():
        kind = "physical" if key in PHYSICAL_BOUNDS else "idle" if key in IDLE_BOUNDS else "artificial"
        out[kind][key] = count
    return out


@dataclass(frozen=True)
class StepRules:
    """Formulation choices of the step (``docs/spec.md``, "Heel strike and lift-off" and "Cost features";
    the evidence: ``docs/gait_regime.md``).

    Attributes:
        liftoff: ``"paper"`` (the benchmark's): the trailing (old stance) foot leaves the
            ground at heel strike with zero velocity and may take a non-pulling ground
            impulse in the impact ("the foot velocity when leaving the ground is zero");
            ``"relaxed"``: it takes no impulse and leaves with zero or upward velocity.
        cost: ``"per-time"`` (the benchmark's): minimise ``w . phi``, the features being
            effort per unit time; ``"per-step"``: minimise ``w . phi`` times the step
            duration, i.e. the effort features summed over the step as printed.
    """

    liftoff: str = "paper"
    cost: str = "per-time"

    def __post_init__(self) -> None:
        if self.liftoff not in ("paper", "relaxed"):
            raise ValueError(f"liftoff must be 'paper' or 'relaxed', got {self.liftoff!r}")
        if self.cost not in ("per-time", "per-step"):
            raise ValueError(f"cost must be 'per-time' or 'per-step', got {self.cost!r}")


@dataclass(frozen=True, eq=False)
class SymbolicStep:
    """The step problem as CasADi expressions (one object per built problem).

    The objective without tracking is ``weights . weighted_features + regularizer``.

    Attributes:
        x: decision vector symbol.
        p: parameter vector symbol.
        g: constraint expressions (bounds per solve, see :meth:`StepProblem.constraint_bounds`).
        weighted_features: ``scale * phi`` over :attr:`features`, the objective's derivative
            by the weights.
        regularizer: the weight-independent lock penalty.
        features: the names of the features, in weight order.
    """

    x: ca.SX
    p: ca.SX
    g: ca.SX
    weighted_features: ca.SX
    regularizer: ca.SX
    features: tuple[str, ...]


@dataclass(frozen=True)
class Bounds:
    """Simple bounds on the decision variables (knot spacing and magnitudes)."""

    dt: tuple[float, float] = (0.004, 0.1)
    position: float = 3.0
    velocity: float = 10.0
    force: float = 20.0
    impulse: float = 5.0


class StepProblem:
    """The periodic-step NLP of one gait model, transcribed with Hermite-Simpson.

    Attributes:
        model: the gait model.
        transcription: the time discretization.
        features: the names of the features the objective weighs, in weight order (by
            default :func:`~ioc_bench.features.model_features`; any of the model's
            :func:`~ioc_bench.features.available_features` may be given).
        layout: named blocks of the decision vector.
        params: named blocks of the parameter vector.
        constraints: named constraint groups and their default bounds.
        casadi_nlp: the CasADi NLP dict ``{x, p, f, g}``.
        features_fn: ``(x, p) -> phi``.
        effort_fn: ``(x, p) -> w . phi`` (times the duration under ``cost="per-step"``).
        regularizer_fn: ``(x, p) -> rho * lock complementarity`` (the weight-independent
            objective term).
        acc_fn: ``(x, p) -> (T*S*3,)`` segment accelerations.
        lock_fn: ``(x, p) -> complementarity products`` (zero at a valid solution).
    """

    def __init__(self, model: GaitModel, n_intervals: int = DEFAULT_INTERVALS, features: Sequence[str] | None = None):
        self.model = model
        self.transcription = HermiteSimpson(n_intervals)
        self.linkage = model.linkage(model.default_params)
        self.roles = model.roles
        self.features = model_features(model) if features is None else check_model_names(model, tuple(features))
        self.seg_names = tuple(s.name for s in self.linkage.segments)
        self.actuators = tuple(j.name for j in self.linkage.actuated)
        self.locks = tuple(j.name for j in self.linkage.locked)
        self.contact = self.linkage.pin_index(self.roles.contact_pin)
        self.segment_swap = permutation(self.seg_names, self.roles.swap_segments)
        self.lock_swap = permutation(self.locks, self.roles.swap_joints)
        self._declare()
        self._build()

    @cached_property
    def symbolic(self) -> SymbolicStep:
        """The NLP's symbolic pieces, for methods that build their own NLP around it."""
        x, p = self.casadi_nlp["x"], self.casadi_nlp["p"]
        return SymbolicStep(
            x=x,
            p=p,
            g=self.g_fn(x, p),
            weighted_features=self.weight_basis,
            regularizer=self.regularizer_fn(x, p),
            features=self.features,
        )

    @property
    def n_intervals(self) -> int:
        return self.transcription.n_intervals

    @property
    def n_knots(self) -> int:
        return self.transcription.n_knots

    # -- declaration --------------------------------------------------------------------
    def _declare(self) -> None:
        t, s, p = self.n_knots, len(self.seg_names), len(self.linkage.pins)
        a, lk = len(self.actuators), len(self.locks)
        self.layout = Layout()
        self.transcription.add_variables(self.layout)
        for name, shape in (
            ("q", (t, s, 3)),
            ("v", (t, s, 3)),
            ("force", (t, p, 2)),
            ("tau", (t, a)),
            ("lock", (t, lk)),
            ("impulse", (p, 2)),
            ("trail_impulse", (2,)),
            ("lock_impulse", (lk,)),
        ):
            self.layout.add(name, shape)
        self.n_track = s * 6 + a
        self.params = Layout()
        for name, shape in (
            ("weights", (len(self.features),)),
            ("scale", (1,)),
            ("speed", (1,)),
            ("friction", (1,)),
            ("lock_range", (1,)),
            ("lock_penalty", (1,)),
            ("per_step", (1,)),
            ("linkage", (len(self.linkage.parameter_vector()),)),
            ("ref", (t, self.n_track)),
            ("track", (t, self.n_track)),
            ("smoothing", (1,)),
        ):
            self.params.add(name, shape)

    # -- construction -------------------------------------------------------------------
    def _build(self) -> None:
        x = ca.SX.sym("x", self.layout.size)
        par = ca.SX.sym("p", self.params.size)
        var = self.layout.views(x)
        prm = self.params.views(par)
        link = self.linkage.with_parameters(list(prm["linkage"]))
        step = prm["speed"][0] * self.transcription.duration(var["dt"])
        acc = [self._acc(link, var, k) for k in range(self.n_knots)]
        flex = self._flexion(link, var["q"][:, :, 2])
        g = Constraints()
        self._dynamics(g, var, acc)
        self._pins(g, link, var, acc)
        self._ground(g, link, var, prm, step)
        g.add("knee_range", [e for f in flex.ravel() for e in (f, prm["lock_range"][0] - f)], 0.0, ca.inf)
        self._joint_ranges(g, link, var["q"][:, :, 2])
        self._impact(g, link, var, prm, step)
        g.add("step_length", [step], 0.0, ca.inf)
        lock_products = self._lock_products(var, flex)
        inputs = step_inputs(self.model, link, var["dt"], var["q"], var["tau"], var["v"])
        phi = feature_vector(inputs, self.features)
        track = np.concatenate(
            [var["q"].reshape(self.n_knots, -1), var["v"].reshape(self.n_knots, -1), var["tau"]], axis=1
        )
        tracking = np.sum(prm["track"] * (track - prm["ref"]) ** 2)
        curvature = var["tau"][2:] - 2 * var["tau"][1:-1] + var["tau"][:-2]  # torque second differences
        tracking = tracking + prm["smoothing"][0] * np.sum(curvature**2)
        per_step = prm["per_step"][0]
        per_weight = phi * (1 - per_step + per_step * inputs.duration)  # the effort is w . per_weight
        effort = ca.dot(ca.vertcat(*prm["weights"]), per_weight)
        regularizer = prm["lock_penalty"][0] * ca.sum1(lock_products)
        objective = prm["scale"][0] * effort + tracking + regularizer
        self.constraints = g
        self.casadi_nlp = {"x": x, "p": par, "f": objective, "g": g.vector()}
        self.features_fn = ca.Function("features", [x, par], [phi])
        self.weight_basis = prm["scale"][0] * per_weight  # d(objective)/d(weights), symbolic
        self.effort_fn = ca.Function("effort", [x, par], [effort])
        self.regularizer_fn = ca.Function("regularizer", [x, par], [regularizer])
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
        joints = [j for j in link.joints if j.lock]
        return np.array([[joint_angle(link, j, th) for j in joints] for th in theta], dtype=object).reshape(
            len(theta), len(joints)
        )

    def _joint_ranges(self, g: Constraints, link: Linkage, theta: np.ndarray) -> None:
        """Hard limits of the joints that have a range and no lock (group ``joint_range``)."""
        if not link.limited:
            return
        exprs = []
        for th in theta:
            for joint in link.limited:
                angle = joint_angle(link, joint, th)
                exprs += [angle - joint.range[0], joint.range[1] - angle]
        g.add("joint_range", exprs, 0.0, ca.inf)

    def _dynamics(self, g: Constraints, var: dict, acc: list) -> None:
        """Collocate every segment's angle and angular velocity.

        A tree-shaped linkage held to the ground by one pin has the segment angles as
        independent coordinates: the pins (enforced at position, velocity and acceleration
        level at every knot, see :meth:`_pins`) fix each segment's translation from them.
        Collocating the translations as well would constrain them twice; their defects
        are the discretization error and are reported, not imposed.
        """
        angles = np.stack([var["q"][:, :, 2], var["v"][:, :, 2]], axis=2).reshape(self.n_knots, -1)
        alpha = np.array([[a[2] for a in kn] for kn in acc], dtype=object)
        rates = np.stack([var["v"][:, :, 2], alpha], axis=2).reshape(self.n_knots, -1)
        self.transcription.add_constraints(g, var["dt"], angles, rates)

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
        foot = [ground_gap(link.segments[i], point, var["q"][k][i]) for k in range(self.n_knots)]
        g.add("swing_clearance", [z for _, z in foot[1:-1]], 0.0, ca.inf)
        g.add("landing", [foot[-1][1], foot[-1][0] - step])

    def _impact(self, g: Constraints, link: Linkage, var: dict, prm: dict, step: Any) -> None:
        """Inelastic heel strike into the relabelled initial state, shifted one step back.

        Impulse balance on every segment with the new stance foot pinned (its vertical
        impulse >= 0, inside the friction cone) and locks able to take impulses. The old
        stance foot's post-impact velocity and its own ground impulse follow
        :class:`StepRules` through per-solve bounds (:meth:`constraint_bounds`,
        :meth:`variable_bounds`).
        """
        last = self.n_knots - 1
        q_pre, v_pre = var["q"][last], var["v"][last]
        v_post = var["v"][0][self.segment_swap]  # post-impact velocities, pre-impact labels
        impact_link = _impact_linkage(link, self.roles)
        impulses = [tuple(f) for f in var["impulse"]] + [tuple(var["trail_impulse"])]
        wrench = pin_wrenches(impact_link, q_pre, impulses)
        lock_moments = joint_moments(link, dict(zip(self.locks, var["lock_impulse"])))
        balance = []
        for i, seg in enumerate(link.segments):
            dv = v_post[i] - v_pre[i]
            balance += [seg.mass * dv[0] - wrench[i][0], seg.mass * dv[1] - wrench[i][1]]
            balance += [seg.inertia * dv[2] - wrench[i][2] - lock_moments[i]]
        g.add("impact", balance)
        g.add("impact_friction", _cone(prm["friction"][0], *var["impulse"][self.contact]), 0.0, ca.inf)
        g.add("trail_friction", _cone(prm["friction"][0], *var["trail_impulse"]), 0.0, ca.inf)
        seg_name, point = self.roles.stance_foot
        j = self.seg_names.index(seg_name)
        lift = ground_gap_rate(link.segments[j], point, q_pre[j], v_post[j])
        g.add("liftoff_x", [lift[0]])
        g.add("liftoff_z", [lift[1]])
        shift = np.array([step, 0, 0], dtype=object)
        g.add("periodicity", (var["q"][0][self.segment_swap] - (q_pre - shift)).ravel())

    def _lock_products(self, var: dict, flex: np.ndarray) -> ca.SX:
        """Lock complementarity as products of non-negative terms (all zero when valid).

        A lock torque at knot k needs full extension at k and at the next knot, so the lock
        can stop a joint but never push it open (it adds no energy). After the last knot
        comes the post-impact motion, where the same joint carries its partner's label.
        """
        lock, lam = var["lock"], var["lock_impulse"]
        last = self.n_knots - 1
        products = []
        for i in range(len(self.locks)):
            after_impact = flex[1, self.lock_swap[i]]
            for k in range(self.n_knots):
                following = flex[k + 1, i] if k < last else after_impact
                products.append(lock[k, i] * (flex[k, i] + following + 2 * LOCK_SLACK))
            products.append(lam[i] * (flex[last, i] + after_impact + 2 * LOCK_SLACK))
        return ca.vertcat(*products) if products else ca.SX(0, 1)

    # -- numeric inputs -----------------------------------------------------------------
    def parameter_vector(
        self,
        params: GaitParams,
        speed: float,
        weights: np.ndarray,
        ref: np.ndarray | None = None,
        track: np.ndarray | None = None,
        smoothing: float = 0.0,
        scale: float = OBJECTIVE_SCALE,
        lock_penalty: float = LOCK_PENALTY,
        rules: StepRules = StepRules(),
    ) -> np.ndarray:
        """The NLP parameter vector for one solve (``weights`` over :attr:`features`)."""
        return self.params.pack(
            {
                "weights": weights,
                "scale": scale,
                "speed": speed,
                "friction": params.friction,
                "lock_range": params.lock_range,
                "lock_penalty": lock_penalty,
                "per_step": float(rules.cost == "per-step"),
                "linkage": self.model.linkage(params).parameter_vector(),
                "ref": 0.0 if ref is None else ref,
                "track": 0.0 if track is None else track,
                "smoothing": smoothing,
            }
        )

    def constraint_bounds(self, step_length: float | None, rules: StepRules) -> tuple[np.ndarray, np.ndarray]:
        """Lower and upper constraint bounds for a task's step length and the lift-off rule."""
        lb, ub = np.array(self.constraints.lb), np.array(self.constraints.ub)
        groups = self.constraints.groups
        if step_length is not None:
            lb[groups["step_length"]] = ub[groups["step_length"]] = step_length
        if rules.liftoff == "relaxed":
            lb[groups["liftoff_x"]], ub[groups["liftoff_x"]] = -ca.inf, ca.inf
            ub[groups["liftoff_z"]] = ca.inf
        return lb, ub

    def variable_bounds(
        self, params: GaitParams, rules: StepRules = StepRules(), bounds: Bounds = Bounds()
    ) -> tuple[np.ndarray, np.ndarray]:
        """Lower and upper bounds on the decision vector."""
        mag = {
            "dt": bounds.dt,
            "q": (-bounds.position, bounds.position),
            "v": (-bounds.velocity, bounds.velocity),
            "force": (-bounds.force, bounds.force),
            "tau": (-params.max_torque, params.max_torque),
            "lock": (0.0, bounds.force),
            "impulse": (-bounds.impulse, bounds.impulse),
            "trail_impulse": (-bounds.impulse, bounds.impulse),
            "lock_impulse": (0.0, bounds.impulse),
        }
        lower = self.layout.unpack(self.layout.pack({k: lo for k, (lo, _) in mag.items()}))
        upper = self.layout.unpack(self.layout.pack({k: hi for k, (_, hi) in mag.items()}))
        # The ground can only push: vertical contact force and impulses are >= 0.
        lower["force"][:, self.contact, 1] = 0.0
        lower["impulse"][self.contact, 1] = 0.0
        lower["trail_impulse"][1] = 0.0
        if rules.liftoff == "relaxed":
            lower["trail_impulse"][:] = upper["trail_impulse"][:] = 0.0
        return self.layout.pack(lower), self.layout.pack(upper)


def _cone(mu: Any, fx: Any, fz: Any) -> list[Any]:
    """Friction cone |fx| <= mu fz as two expressions that must be >= 0."""
    return [mu * fz - fx, mu * fz + fx]


def _impact_linkage(link: Linkage, roles: GaitRoles) -> Linkage:
    """The linkage at heel strike: the contact pin moves to the landing swing foot, and a
    last pin ("trail") holds the trailing foot, whose impulse :class:`StepRules` may allow."""
    seg, point = roles.swing_foot
    pins = tuple(Pin(p.name, seg, point, None, (0.0, 0.0)) if p.name == roles.contact_pin else p for p in link.pins)
    trail = Pin("trail", *roles.stance_foot, None, (0.0, 0.0))
    return replace(link, pins=(*pins, trail))
