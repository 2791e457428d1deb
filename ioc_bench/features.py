"""Cost features of a walking step: one definition for the optimizer, the IOC, scoring and the env.

Each effort feature is defined once, by its per-knot *increment* (the paper's summand,
section II.B). The step's feature is the sum of its increments over the knots divided by
the step's duration, i.e. the effort per unit time (``docs/gait_regime.md`` says why); the
Gymnasium environment rewards the same increments step by step. Everything is in the
units the paper's numbers are in: SI units of a walker with leg 1 m and mass 1 kg under
g = 9.81 m/s^2 (torques in N m, time in s, energy in J), while the model itself stays
dimensionless.

Besides the benchmark's features (the efforts and the paper's distractors, which
:func:`model_features` lists) there are features that price what people are found to
minimise, the actuators' positive work (``work``) and the energy heel strike dissipates
(``collision``) (``docs/spec.md``, "Work and collision features"). They read the step's
velocities, are no default of any list, and are weighed only when asked for by name
(:func:`available_features` lists every feature a model can have).

The trajectory optimizer builds the features symbolically from its variables with
:func:`feature_vector`; :class:`FeatureMap` compiles the very same expression once per
model into a CasADi function for numbers, gradients and Hessians.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from functools import lru_cache
from typing import Any

import casadi as ca
import numpy as np

from ioc_bench.model.gait_model import GaitModel, permutation
from ioc_bench.model.linkage import Linkage, ground_gap
from ioc_bench.model.walker import WALKER
from ioc_bench.trajectory import Observation

#: Gravity of the paper's units: features are SI values for a 1 m, 1 kg walker.
PAPER_GRAVITY = 9.81
#: Newton metres per model torque unit (m g L with m = 1 kg, L = 1 m).
TORQUE_UNIT = PAPER_GRAVITY
#: Seconds per model time unit (sqrt(L / g)).
TIME_UNIT = PAPER_GRAVITY**-0.5
#: Target step length of the ``steplen`` distractor (``docs/spec.md``, "Distractor features"), metres (= leg lengths).
STEPLEN_TARGET = 0.3
#: Scale of the torque-rate feature, "due to unit differences" (the paper).
DTAU_SCALE = 0.001
#: Joules per model energy unit (m g L).
ENERGY_UNIT = PAPER_GRAVITY
#: Watts per model power unit (m g L per sqrt(L / g)).
POWER_UNIT = ENERGY_UNIT / TIME_UNIT
#: Width eps of the smoothed positive part in the ``work`` feature, W. ``(p + sqrt(p^2 + eps^2)) / 2``
#: exceeds ``max(p, 0)`` by eps / 2 at p = 0 and by about eps^2 / (4 |p|) away from it, and
#: its curvature is at most 1 / (2 eps). The width is what lets the optimizer price work
#: alone: on a person's speed (WBDS01, T05), hip + work and work + collision converge from
#: 16 of 16 starts in 79-169 iterations at 0.3 W, 15 of 16 in 212-500 at 0.1 W, and none
#: within 500 at 0.01 W (``docs/spec.md``, "Work and collision features"). The cost is a
#: feature up to eps / 2 per joint above the exact positive work where a joint's power
#: crosses zero, against the walker's mean positive work of 0.2-2.6 W.
WORK_SMOOTHING = 0.3


@dataclass(frozen=True)
class FeatureInputs:
    """What the features read from a step of T knots (numbers or CasADi scalars).

    The velocity fields are None when the step's velocities were not given; the features
    that read them (``work``, ``collision``) then raise ``ValueError``.

    Attributes:
        dt: (T,) knot spacing in model time units (one copy per knot inside the optimizer).
        tau: (T, A) actuated torques in model units, columns in the model's actuator order.
        groups: column indices of each actuator group (e.g. ``{"hip": [0, 1]}``).
        torso: (T,) torso angle from vertical, rad.
        foot_z: (T,) swing-foot height, leg lengths.
        step_length: landing distance of the swing foot ahead of the stance foot.
        mass: (S,) segment masses, model units (the linkage's, possibly symbolic).
        inertia: (S,) segment moments of inertia about their centres of mass, model units.
        v: (T, S, 3) segment velocities ``(xdot, zdot, thetadot)``, model units.
        v_post: (S, 3) segment velocities just after heel strike, in the labels of before
            it (the first knot's velocities relabelled by the swap of legs).
        joint_rate: (T, A) rate of each actuated joint's angle, ``thetadot_child -
            thetadot_parent``, columns as ``tau``'s.
    """

    dt: Sequence[Any]
    tau: Sequence[Sequence[Any]]
    groups: Mapping[str, Sequence[int]]
    torso: Sequence[Any]
    foot_z: Sequence[Any]
    step_length: Any
    mass: Sequence[Any] | None = None
    inertia: Sequence[Any] | None = None
    v: Sequence[Sequence[Sequence[Any]]] | None = None
    v_post: Sequence[Sequence[Any]] | None = None
    joint_rate: Sequence[Sequence[Any]] | None = None

    @property
    def duration(self) -> Any:
        """Step duration in seconds (the last knot's spacing copy times the intervals)."""
        return TIME_UNIT * self.dt[-1] * (len(self.dt) - 1)


Increment = Callable[[Sequence[Any], Sequence[Any], Any, Mapping[str, Sequence[int]]], Any]


@dataclass(frozen=True)
class Feature:
    """A cost feature.

    Attributes:
        name: the feature's name.
        description: its formula, in words.
        unit: the unit of its value.
        value: ``FeatureInputs -> value`` over a whole step.
        increment: for effort features, the per-knot term ``(tau, tau_prev, dt, groups)``
            (tau rows in model units, dt in model time units; result in the paper's units)
            whose sum over a step's knots, divided by the step's duration, is ``value``.
        requires: the actuator group the feature needs (a model without it lacks the feature).
        in_default_basis: whether :func:`model_features` lists it (the benchmark's
            features: efforts and distractors). A feature outside the default basis is
            weighed only when asked for by name (:func:`available_features`); it is neither
            an effort nor a distractor of the benchmark's lists, whatever its increment.
    """

    name: str
    description: str
    unit: str
    value: Callable[[FeatureInputs], Any]
    increment: Increment | None = None
    requires: str | None = None
    in_default_basis: bool = True


def _effort_increment(group: str) -> Increment:
    def increment(tau, prev, dt, groups):
        return sum((TORQUE_UNIT * tau[c]) ** 2 for c in groups[group]) * (TIME_UNIT * dt)

    return increment


def _rate_increment(tau, prev, dt, groups) -> Any:
    h = TIME_UNIT * dt
    return DTAU_SCALE * sum((TORQUE_UNIT * (tau[c] - prev[c]) / h) ** 2 for c in range(len(tau))) * h


def _per_time(increment: Increment) -> Callable[[FeatureInputs], Any]:
    """Sum of the increments over the knots (knot 0 has itself as predecessor) per second."""

    def value(f: FeatureInputs) -> Any:
        total = sum(increment(f.tau[t], f.tau[max(t - 1, 0)], f.dt[t], f.groups) for t in range(len(f.dt)))
        return total / f.duration

    return value


def _given(f: FeatureInputs, field: str, feature: str) -> Any:
    value = getattr(f, field)
    if value is None:
        raise ValueError(f"feature {feature!r} reads the step's velocities: give them to step_inputs (v=...)")
    return value


def _smooth_positive(p: Any) -> Any:
    """``max(p, 0)`` rounded over :data:`WORK_SMOOTHING` (W), differentiable everywhere."""
    return (p + ca.sqrt(p * p + WORK_SMOOTHING**2)) / 2


def _positive_work(f: FeatureInputs) -> Any:
    """Positive work of the actuated joints per second of step, W.

    A joint torque acts ``+tau`` on its child segment and ``-tau`` on its parent
    (:func:`~ioc_bench.model.linkage.joint_moments`), so the power it delivers is
    ``tau thetadot_child - tau thetadot_parent = tau * joint_rate`` (the pin's constraint
    forces do no net work). The smoothed positive part of each joint's power is summed over
    the knots times their spacing, as the efforts are, and divided by the step's duration.
    """
    rates = _given(f, "joint_rate", "work")
    total = 0
    for t in range(len(f.dt)):
        power = sum(_smooth_positive(POWER_UNIT * tau * rate) for tau, rate in zip(f.tau[t], rates[t]))
        total = total + power * (TIME_UNIT * f.dt[t])
    return total / f.duration


def _kinetic_energy(mass: Sequence[Any], inertia: Sequence[Any], v: Sequence[Sequence[Any]]) -> Any:
    """Kinetic energy of the segments, model units: sum of m (xdot^2 + zdot^2) / 2 + I thetadot^2 / 2."""
    return sum(m * (vx * vx + vz * vz) / 2 + i * w * w / 2 for m, i, (vx, vz, w) in zip(mass, inertia, v))


def _collision(f: FeatureInputs) -> Any:
    """Kinetic energy heel strike removes per second of step, W: the last knot's kinetic
    energy minus that of the post-impact velocities, over the step's duration."""
    v, v_post = _given(f, "v", "collision"), _given(f, "v_post", "collision")
    loss = _kinetic_energy(f.mass, f.inertia, v[-1]) - _kinetic_energy(f.mass, f.inertia, v_post)
    return ENERGY_UNIT * loss / f.duration


def _effort(name: str, group: str) -> Feature:
    inc = _effort_increment(group)
    return Feature(
        name,
        f"mean squared {group} torque: sum_t (tau_{group}_swing^2 + tau_{group}_stance^2) dT / step duration",
        "N^2 m^2",
        _per_time(inc),
        inc,
        requires=group,
    )


FEATURES: dict[str, Feature] = {
    f.name: f
    for f in (
        _effort("hip", "hip"),
        _effort("knee", "knee"),
        _effort("ankle", "ankle"),
        Feature(
            "dtau",
            "mean squared torque rate: 0.001 sum_t sum_j ((tau_j,t+1 - tau_j,t) / dT)^2 dT / step duration",
            "N^2 m^2 / s^2",
            _per_time(_rate_increment),
            _rate_increment,
        ),
        Feature(
            "torso",
            "mean squared torso angle: sum_t theta_torso^2 dT / step duration",
            "rad^2",
            lambda f: sum(th**2 * dt for th, dt in zip(f.torso, f.dt)) * TIME_UNIT / f.duration,
        ),
        Feature(
            "steplen",
            "(step length - 0.3)^2",
            "m^2",
            lambda f: (f.step_length - STEPLEN_TARGET) ** 2,
        ),
        Feature("footheight", "mean swing-foot height over the knots", "m", lambda f: sum(f.foot_z) / len(f.foot_z)),
        Feature(
            "work",
            "positive work of the actuated joints per second: sum_t sum_j pos(tau_j,t omega_j,t) dT / step duration, "
            f"omega the joint's rate (child minus parent), pos(p) = (p + sqrt(p^2 + {WORK_SMOOTHING}^2)) / 2",
            "W",
            _positive_work,
            in_default_basis=False,
        ),
        Feature(
            "collision",
            "kinetic energy heel strike removes per second: (KE before impact - KE after) / step duration",
            "W",
            _collision,
            in_default_basis=False,
        ),
    )
}


def available_features(model: GaitModel) -> tuple[str, ...]:
    """Every feature a model can have, in :data:`FEATURES` order: all but those whose
    actuator group the model lacks (the default basis and the features asked for by name)."""
    return tuple(n for n, f in FEATURES.items() if f.requires in (None, *model.actuator_groups))


def model_features(model: GaitModel) -> tuple[str, ...]:
    """The features a model has, in weight order: its :func:`available_features` of the
    default basis (efforts and distractors; ``work`` and ``collision`` only by name)."""
    return tuple(n for n in available_features(model) if FEATURES[n].in_default_basis)


def efforts(names: Sequence[str]) -> tuple[str, ...]:
    """The effort features among ``names``, in their order: features of the default basis
    with a per-knot increment (any model's: the ankle's too, not only the walker's)."""
    return tuple(n for n in names if n in FEATURES and _is_effort(FEATURES[n]))


def _is_effort(feature: Feature) -> bool:
    return feature.in_default_basis and feature.increment is not None


def cost_features(model: GaitModel) -> tuple[str, ...]:
    """The effort features a model's demonstrations are made with, in weight order: its
    features with a per-knot increment (the others are distractors). Features outside the
    default basis are in neither list."""
    return efforts(model_features(model))


#: The walker's effort features, in weight order: ``cost_features(WALKER)``.
COST_FEATURES: tuple[str, ...] = cost_features(WALKER)
#: The walker's features: what the benchmark's optimizer and IOC weigh (``model_features(WALKER)``).
ALL_FEATURES: tuple[str, ...] = model_features(WALKER)
#: Distractors: the walker's features that are no effort; offered to the IOC in the distractor
#: condition, true weight 0.
DISTRACTORS: tuple[str, ...] = tuple(f for f in ALL_FEATURES if f not in COST_FEATURES)


def check_names(names: Sequence[str]) -> tuple[str, ...]:
    """Validate feature names (any of :data:`FEATURES`), raising ``ValueError`` that lists the valid ones."""
    unknown = [n for n in names if n not in FEATURES]
    if unknown or not names:
        raise ValueError(f"unknown feature(s) {unknown or names}; valid: {', '.join(FEATURES)}")
    return tuple(names)


def check_model_names(model: GaitModel, names: Sequence[str]) -> tuple[str, ...]:
    """Validate feature names (:func:`check_names`) that ``model`` has (its
    :func:`available_features`), raising ``ValueError`` that lists the model's features."""
    names = check_names(names)
    missing = [n for n in names if n not in available_features(model)]
    if missing:
        raise ValueError(
            f"model {model.name!r} has no feature(s) {missing}; it has: {', '.join(available_features(model))}"
        )
    return names


def group_columns(model: GaitModel, actuators: Sequence[str]) -> dict[str, list[int]]:
    """Column indices of each of the model's actuator groups in ``actuators`` order."""
    return {g: [actuators.index(j) for j in joints] for g, joints in model.actuator_groups.items()}


def step_inputs(
    model: GaitModel, linkage: Linkage, dt: Sequence[Any], q: Any, tau: Any, v: Any = None
) -> FeatureInputs:
    """:class:`FeatureInputs` of a step from its knot spacings, segment positions (T, S, 3),
    torques (T, A) and, for the features that read them, segment velocities (T, S, 3);
    numbers and CasADi scalars alike.

    The post-impact velocities are the first knot's, relabelled by the model's swap of legs
    (``GaitRoles.swap_segments``), as the step's impact and periodicity have them."""
    roles = model.roles
    n = len(dt)
    i_foot, i_torso = linkage.index(roles.swing_foot[0]), linkage.index(roles.torso)
    segment = linkage.segments[i_foot]
    foot = [ground_gap(segment, roles.swing_foot[1], q[k][i_foot]) for k in range(n)]
    actuators = [j.name for j in linkage.actuated]
    velocities: dict[str, Any] = {}
    if v is not None:
        segments = range(len(linkage.segments))
        swap = permutation(tuple(s.name for s in linkage.segments), roles.swap_segments)
        joints = [(linkage.index(j.child), linkage.index(j.parent)) for j in linkage.actuated]
        velocities = {
            "v": [[list(v[k][i]) for i in segments] for k in range(n)],
            "v_post": [list(v[0][i]) for i in swap],
            "joint_rate": [[v[k][c][2] - v[k][p][2] for c, p in joints] for k in range(n)],
        }
    return FeatureInputs(
        dt=list(dt),
        tau=[list(row) for row in tau],
        groups=group_columns(model, actuators),
        torso=[q[k][i_torso][2] for k in range(n)],
        foot_z=[z for _, z in foot],
        step_length=foot[-1][0],
        mass=[s.mass for s in linkage.segments],
        inertia=[s.inertia for s in linkage.segments],
        **velocities,
    )


def feature_vector(inputs: FeatureInputs, names: Sequence[str]) -> ca.SX:
    """The named features of ``inputs`` as a CasADi column (symbolic inside the optimizer)."""
    return ca.vertcat(*[FEATURES[n].value(inputs) for n in check_names(names)])


class FeatureMap:
    """A model's features over its steps of ``n_knots`` knots, compiled once.

    ``phi(x, linkage_parameters)`` with ``x = (dt, q, v, tau)`` (:attr:`blocks`) is the
    same expression the optimizer puts in its objective; :meth:`jacobian` and
    :meth:`hessian` differentiate it. ``names`` defaults to :func:`model_features`; any of
    the model's :func:`available_features` may be asked for.
    """

    def __init__(self, model: GaitModel, n_knots: int, names: Sequence[str] | None = None):
        self.model = model
        self.names = check_model_names(model, tuple(names) if names is not None else model_features(model))
        link = model.linkage(model.default_params)
        s, a = len(link.segments), len(link.actuated)
        sizes = {"dt": n_knots, "q": n_knots * s * 3, "v": n_knots * s * 3, "tau": n_knots * a}
        starts = np.cumsum([0, *sizes.values()])
        #: Where each input block lies in ``x``.
        self.blocks = {name: slice(int(lo), int(hi)) for name, lo, hi in zip(sizes, starts[:-1], starts[1:])}
        dt, q, v, tau = (ca.SX.sym(name, size) for name, size in sizes.items())
        lp = ca.SX.sym("lp", len(link.parameter_vector()))
        sym = link.with_parameters(ca.vertsplit(lp))

        def per_segment(z: ca.SX) -> list:
            return [[ca.vertsplit(z[(k * s + i) * 3 : (k * s + i + 1) * 3]) for i in range(s)] for k in range(n_knots)]

        tau_knots = [ca.vertsplit(tau[k * a : (k + 1) * a]) for k in range(n_knots)]
        inputs = step_inputs(model, sym, ca.vertsplit(dt), per_segment(q), tau_knots, per_segment(v))
        phi = feature_vector(inputs, self.names)
        x = ca.vertcat(dt, q, v, tau)
        self.phi = ca.Function("phi", [x, lp], [phi])
        self.jac = ca.Function("phi_jac", [x, lp], [ca.jacobian(phi, x)])
        self._x = x
        self._lp = lp
        self._expr = phi

    def inputs(self, traj: Observation) -> np.ndarray:
        """The step's (dt, q, v, tau) as one flat vector (the order :attr:`phi` takes)."""
        if traj.tau is None:
            raise ValueError("the step's torques were not measured; project it to a full trajectory first")
        return np.concatenate([np.full(traj.n_knots, traj.dt), traj.q.ravel(), traj.v.ravel(), traj.tau.ravel()])

    def __call__(self, traj: Observation, params: Any) -> np.ndarray:
        """(F,) feature values of a step under model ``params``."""
        lp = self.model.linkage(params).parameter_vector()
        return np.asarray(self.phi(self.inputs(traj), lp), dtype=float).ravel()

    def jacobian(self, traj: Observation, params: Any) -> np.ndarray:
        """(F, n) derivatives of the features by (dt at every knot, q, v, tau) of a step."""
        lp = self.model.linkage(params).parameter_vector()
        return np.asarray(self.jac(self.inputs(traj), lp), dtype=float)

    def hessian(self, index: int) -> ca.Function:
        """``(x, lp) -> Hessian`` of feature ``index`` in the (dt, q, v, tau) inputs."""
        h, _ = ca.hessian(self._expr[index], self._x)
        return ca.Function(f"phi_hess_{self.names[index]}", [self._x, self._lp], [h])


@lru_cache(maxsize=8)
def feature_map(model: GaitModel = WALKER, n_knots: int = 41, names: tuple[str, ...] | None = None) -> FeatureMap:
    """This process's :class:`FeatureMap` for a model and knot count (built on first use)."""
    return FeatureMap(model, n_knots, names)


def evaluate(
    traj: Observation, params: Any, names: Sequence[str] = ALL_FEATURES, model: GaitModel = WALKER
) -> dict[str, float]:
    """Feature values of a trajectory under model ``params``, by name (any of the model's
    :func:`available_features`)."""
    names = check_model_names(model, names)
    by_name = set(names) - set(model_features(model))
    fmap = feature_map(model, traj.n_knots, available_features(model) if by_name else None)
    values = dict(zip(fmap.names, fmap(traj, params)))
    return {n: float(values[n]) for n in names}
