"""Robustness conditions (``docs/spec.md``, "Conditions") as data: how what the IOC sees differs from the truth.

A condition says at which speed the demonstration is made, and how the IOC's view differs:
noise on the observed step (and whether torques are measured at all), a different model
(leg mass), a different task (speed), extra (distractor) features. Beyond the paper's
single sizes, conditions along three axes (noise, leg-mass error, speed error) at several
severities give robustness curves (``axis`` and ``severity``; the ``robustness`` suite).
Add a condition by adding a :class:`Condition` to :data:`CONDITIONS` (or
:func:`register_condition`); the runner needs no change.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

from ioc_bench.features import ALL_FEATURES, COST_FEATURES, available_features
from ioc_bench.model.gait_model import GaitModel, GaitParams
from ioc_bench.task import FAST_SPEED, NOMINAL_SPEED, Task


@dataclass(frozen=True)
class Condition:
    """One way the IOC's view of a demonstration can be imperfect.

    Attributes:
        name: unique name.
        description: one line for tables and help.
        demo_speed: speed of the demonstrated step.
        noise: observation noise, sigma as a fraction of each signal's span (0: none).
        ioc_leg_mass: factor on the leg masses of the IOC's model (torso keeps total 1): the
            thighs and shanks of the walker, the two legs of the compass walker (every
            model's ``with_leg_mass_scale``).
        ioc_speed: factor on the speed of the IOC's task.
        features: the features the IOC may weigh (those a model lacks are left out for it,
            see :meth:`features_for`: the compass walker has no knee).
        torques: whether the joint torques are measured (else the observation holds
            positions and velocities only; algorithms get torques from their own model).
        axis: the robustness axis the condition lies on (``noise``, ``mass``, ``speed``;
            empty for none), for robustness curves.
        severity: its signed size on that axis, percent (noise sigma, mass or speed error).
        trial_speeds: speeds of several observed trials of one subject (the same weights
            and seed), one weight vector to explain them all (multi-trial IOC); empty: one
            trial at ``demo_speed``.
    """

    name: str
    description: str
    demo_speed: float = NOMINAL_SPEED
    noise: float = 0.0
    ioc_leg_mass: float = 1.0
    ioc_speed: float = 1.0
    features: tuple[str, ...] = COST_FEATURES
    torques: bool = True
    axis: str = ""
    severity: float = 0.0
    trial_speeds: tuple[float, ...] = ()

    def __post_init__(self) -> None:
        if self.trial_speeds:
            object.__setattr__(self, "demo_speed", self.trial_speeds[0])

    @property
    def speeds(self) -> tuple[float, ...]:
        """The speed of every observed trial."""
        return self.trial_speeds or (self.demo_speed,)

    def demo_task(self, trial: int = 0) -> Task:
        return Task(self.speeds[trial])

    def ioc_task(self, trial: int = 0) -> Task:
        return Task(self.speeds[trial] * self.ioc_speed)

    def ioc_params(self, truth: GaitParams) -> GaitParams:
        return truth if self.ioc_leg_mass == 1.0 else truth.with_leg_mass_scale(self.ioc_leg_mass)

    def features_for(self, model: GaitModel, extra: Sequence[str] = ()) -> tuple[str, ...]:
        """The features the IOC may weigh for ``model``: this condition's, then ``extra`` (a
        case's cost basis beyond the model's efforts), those the model has."""
        own = available_features(model)
        names = [f for f in self.features if f in own]
        return (*names, *(f for f in extra if f in own and f not in names))


def _noise(percent: float) -> Condition:
    return Condition(
        f"noise-{percent:g}",
        f"observation + Gaussian noise, sigma {percent:g} % of each signal's span",
        noise=percent / 100,
        axis="noise",
        severity=percent,
    )


#: A model- or task-error axis: its description (with the size and direction of the error),
#: the words for below and above the truth, and the Condition field it scales.
_SCALED_AXES = {
    "mass": ("IOC model: legs {size:g} % {word}, torso keeps the total", ("lighter", "heavier"), "ioc_leg_mass"),
    "speed": ("IOC task {size:g} % {word} than the demonstration", ("slower", "faster"), "ioc_speed"),
}


def _scaled(axis: str, percent: float) -> Condition:
    """The IOC's model or task off by ``percent`` along ``axis``."""
    text, words, field = _SCALED_AXES[axis]
    return Condition(
        f"{axis}{percent:+g}",
        text.format(size=abs(percent), word=words[percent > 0]),
        axis=axis,
        severity=percent,
        **{field: 1 + percent / 100},
    )


CONDITIONS: dict[str, Condition] = {
    c.name: c
    for c in (
        Condition("ideal", "exact model, task and features"),
        Condition("ideal-fast", "exact, at the fast speed 0.34", demo_speed=FAST_SPEED),
        Condition(
            "noise",
            "observation + Gaussian noise, sigma 5 % of each signal's span (torques too: the paper's reading)",
            noise=0.05,
            axis="noise",
            severity=5,
        ),
        Condition(
            "noise-kinematics",
            "positions and velocities + 5 % noise; torques not measured (the IOC's own model supplies them)",
            noise=0.05,
            torques=False,
        ),
        Condition("mass", "IOC model: legs 10 % heavier, torso lighter", ioc_leg_mass=1.1, axis="mass", severity=10),
        Condition("speed", "IOC task 10 % faster than the demonstration", ioc_speed=1.1, axis="speed", severity=10),
        Condition("distractor", "3 distractor features added (true weight 0)", features=ALL_FEATURES),
        Condition(
            "distractor-energetics",
            "positive joint work and the heel-strike collision loss added (true weight 0)",
            features=(*COST_FEATURES, "work", "collision"),
        ),
        Condition(
            "multi-speed",
            "two trials of one subject, at 0.27 and 0.34, exact: one weight vector for both",
            trial_speeds=(NOMINAL_SPEED, FAST_SPEED),
        ),
        Condition(
            "multi-speed-noise",
            "two trials, at 0.27 and 0.34, each + 5 % noise (the first trial's noise is the noise condition's)",
            noise=0.05,
            trial_speeds=(NOMINAL_SPEED, FAST_SPEED),
        ),
        *(_noise(p) for p in (1, 2, 10)),
        *(_scaled("mass", p) for p in (-20, -10, 20)),
        *(_scaled("speed", p) for p in (-20, -10, 20)),
    )
}
#: The conditions of each robustness axis, by severity (ideal is severity 0 on every axis).
AXES: tuple[str, ...] = ("noise", "mass", "speed")


def axis_conditions(axis: str) -> list[Condition]:
    """``ideal`` and every condition on ``axis``, by severity."""
    on_axis = [c for c in CONDITIONS.values() if c.axis == axis]
    return sorted([CONDITIONS["ideal"], *on_axis], key=lambda c: c.severity)


def register_condition(condition: Condition) -> Condition:
    return register(CONDITIONS, condition, "condition")


def get_condition(name: str) -> Condition:
    return lookup(CONDITIONS, name, "condition")


def register(catalogue: dict, item, kind: str):
    """Add ``item`` to a name-keyed catalogue; a duplicate name raises ``ValueError``."""
    if item.name in catalogue:
        raise ValueError(f"{kind} {item.name!r} already exists")
    catalogue[item.name] = item
    return item


def lookup(catalogue: dict, name: str, kind: str):
    """The catalogue's item called ``name``; an unknown name raises, listing the valid ones."""
    try:
        return catalogue[name]
    except KeyError:
        raise ValueError(f"unknown {kind} {name!r}; valid: {', '.join(catalogue)}") from None
