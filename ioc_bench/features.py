"""Cost features of a walking step: one definition for the optimizer, the IOC, scoring and the env.

Each effort feature is defined once, by its per-knot *increment* (the paper's summand,
section II.B). The step's feature is the sum of its increments over the knots divided by
the step's duration, i.e. the effort per unit time (``docs/gait_regime.md`` says why); the
Gymnasium environment rewards the same increments step by step. Everything is in the
units the paper's numbers are in: SI units of a walker with leg 1 m and mass 1 kg under
g = 9.81 m/s^2 (torques in N m, time in s), while the model itself stays dimensionless.

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

from ioc_bench.model.gait_model import GaitModel
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


@dataclass(frozen=True)
class FeatureInputs:
    """What the features read from a step of T knots (numbers or CasADi scalars).

    Attributes:
        dt: (T,) knot spacing in model time units (one copy per knot inside the optimizer).
        tau: (T, A) actuated torques in model units, columns in the model's actuator order.
        groups: column indices of each actuator group (e.g. ``{"hip": [0, 1]}``).
        torso: (T,) torso angle from vertical, rad.
        foot_z: (T,) swing-foot height, leg lengths.
        step_length: landing distance of the swing foot ahead of the stance foot.
    """

    dt: Sequence[Any]
    tau: Sequence[Sequence[Any]]
    groups: Mapping[str, Sequence[int]]
    torso: Sequence[Any]
    foot_z: Sequence[Any]
    step_length: Any

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
    """

    name: str
    description: str
    unit: str
    value: Callable[[FeatureInputs], Any]
    increment: Increment | None = None
    requires: str | None = None


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
    )
}


def model_features(model: GaitModel) -> tuple[str, ...]:
    """The features a model has, in weight order: every feature of :data:`FEATURES` but those
    whose actuator group the model lacks."""
    return tuple(n for n, f in FEATURES.items() if f.requires in (None, *model.actuator_groups))


def cost_features(model: GaitModel) -> tuple[str, ...]:
    """The effort features a model's demonstrations are made with, in weight order: its
    features with a per-knot increment (the others are distractors)."""
    return tuple(n for n in model_features(model) if FEATURES[n].increment is not None)


#: The walker's effort features, in weight order: ``cost_features(WALKER)``.
COST_FEATURES: tuple[str, ...] = cost_features(WALKER)
#: The walker's features: what the benchmark's optimizer and IOC weigh (``model_features(WALKER)``).
ALL_FEATURES: tuple[str, ...] = model_features(WALKER)
#: Distractors: the walker's features that are no effort; offered to the IOC in the distractor
#: condition, true weight 0.
DISTRACTORS: tuple[str, ...] = tuple(f for f in ALL_FEATURES if f not in COST_FEATURES)


def check_names(names: Sequence[str]) -> tuple[str, ...]:
    """Validate feature names, raising ``ValueError`` that lists the valid ones."""
    unknown = [n for n in names if n not in FEATURES]
    if unknown or not names:
        raise ValueError(f"unknown feature(s) {unknown or names}; valid: {', '.join(FEATURES)}")
    return tuple(names)


def group_columns(model: GaitModel, actuators: Sequence[str]) -> dict[str, list[int]]:
    """Column indices of each of the model's actuator groups in ``actuators`` order."""
    return {g: [actuators.index(j) for j in joints] for g, joints in model.actuator_groups.items()}


def step_inputs(model: GaitModel, linkage: Linkage, dt: Sequence[Any], q: Any, tau: Any) -> FeatureInputs:
    """:class:`FeatureInputs` of a step from its knot spacings, segment positions (T, S, 3)
    and torques (T, A); numbers and CasADi scalars alike."""
    roles = model.roles
    i_foot, i_torso = linkage.index(roles.swing_foot[0]), linkage.index(roles.torso)
    segment = linkage.segments[i_foot]
    foot = [ground_gap(segment, roles.swing_foot[1], q[k][i_foot]) for k in range(len(dt))]
    actuators = [j.name for j in linkage.actuated]
    return FeatureInputs(
        dt=list(dt),
        tau=[list(row) for row in tau],
        groups=group_columns(model, actuators),
        torso=[q[k][i_torso][2] for k in range(len(dt))],
        foot_z=[z for _, z in foot],
        step_length=foot[-1][0],
    )


def feature_vector(inputs: FeatureInputs, names: Sequence[str]) -> ca.SX:
    """The named features of ``inputs`` as a CasADi column (symbolic inside the optimizer)."""
    return ca.vertcat(*[FEATURES[n].value(inputs) for n in check_names(names)])


class FeatureMap:
    """A model's features over its steps of ``n_knots`` knots, compiled once.

    ``phi(dt, q, tau, linkage_parameters)`` is the same expression the optimizer puts in
    its objective; :meth:`jacobian` and :meth:`hessian` differentiate it.
    """

    def __init__(self, model: GaitModel, n_knots: int, names: Sequence[str] | None = None):
        self.model = model
        self.names = check_names(tuple(names) if names is not None else model_features(model))
        link = model.linkage(model.default_params)
        s, a = len(link.segments), len(link.actuated)
        self._sizes = (n_knots, n_knots * s * 3, n_knots * a, len(link.parameter_vector()))
        dt, q, tau, lp = (ca.SX.sym(n, k) for n, k in zip(("dt", "q", "tau", "lp"), self._sizes))
        sym = link.with_parameters(ca.vertsplit(lp))
        q_knots = [[ca.vertsplit(q[(k * s + i) * 3 : (k * s + i + 1) * 3]) for i in range(s)] for k in range(n_knots)]
        tau_knots = [ca.vertsplit(tau[k * a : (k + 1) * a]) for k in range(n_knots)]
        phi = feature_vector(step_inputs(model, sym, ca.vertsplit(dt), q_knots, tau_knots), self.names)
        x = ca.vertcat(dt, q, tau)
        self.phi = ca.Function("phi", [x, lp], [phi])
        self.jac = ca.Function("phi_jac", [x, lp], [ca.jacobian(phi, x)])
        self._x = x
        self._lp = lp
        self._expr = phi

    def inputs(self, traj: Observation) -> np.ndarray:
        """The step's (dt, q, tau) as one flat vector (the order :attr:`phi` takes)."""
        if traj.tau is None:
            raise ValueError("the step's torques were not measured; project it to a full trajectory first")
        return np.concatenate([np.full(traj.n_knots, traj.dt), traj.q.ravel(), traj.tau.ravel()])

    def __call__(self, traj: Observation, params: Any) -> np.ndarray:
        """(F,) feature values of a step under model ``params``."""
        lp = self.model.linkage(params).parameter_vector()
        return np.asarray(self.phi(self.inputs(traj), lp), dtype=float).ravel()

    def jacobian(self, traj: Observation, params: Any) -> np.ndarray:
        """(F, n) derivatives of the features by (dt at every knot, q, tau) of a step."""
        lp = self.model.linkage(params).parameter_vector()
        return np.asarray(self.jac(self.inputs(traj), lp), dtype=float)

    def hessian(self, index: int) -> ca.Function:
        """``(x, lp) -> Hessian`` of feature ``index`` in the (dt, q, tau) inputs."""
        h, _ = ca.hessian(self._expr[index], self._x)
        return ca.Function(f"phi_hess_{self.names[index]}", [self._x, self._lp], [h])


@lru_cache(maxsize=8)
def feature_map(model: GaitModel = WALKER, n_knots: int = 41, names: tuple[str, ...] | None = None) -> FeatureMap:
    """This process's :class:`FeatureMap` for a model and knot count (built on first use)."""
    return FeatureMap(model, n_knots, names)


def evaluate(
    traj: Observation, params: Any, names: Sequence[str] = ALL_FEATURES, model: GaitModel = WALKER
) -> dict[str, float]:
    """Feature values of a trajectory under model ``params``, by name."""
    names = check_names(names)
    fmap = feature_map(model, traj.n_knots)
    values = dict(zip(fmap.names, fmap(traj, params)))
    missing = [n for n in names if n not in values]
    if missing:
        raise ValueError(f"model {model.name!r} has no feature(s) {missing}")
    return {n: float(values[n]) for n in names}
