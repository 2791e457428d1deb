"""Robustness conditions (SPEC section 4) as data: how what the IOC sees differs from the truth.

A condition says at which speed the demonstration is made, and how the IOC's view differs:
noise on the observed step, a different model (leg mass), a different task (speed), extra
(distractor) features. Add a condition by adding a :class:`Condition` to
:data:`CONDITIONS` (or :func:`register_condition`); the runner needs no change.
"""

from __future__ import annotations

from dataclasses import dataclass

from ioc_bench.features import ALL_FEATURES, COST_FEATURES
from ioc_bench.model.params import WalkerParams
from ioc_bench.task import FAST_SPEED, NOMINAL_SPEED, Task


@dataclass(frozen=True)
class Condition:
    """One way the IOC's view of a demonstration can be imperfect.

    Attributes:
        name: unique name.
        description: one line for tables and help.
        demo_speed: speed of the demonstrated step.
        noise: observation noise, sigma as a fraction of each signal's span (0: none).
        ioc_leg_mass: factor on the leg masses of the IOC's model (torso keeps total 1).
        ioc_speed: factor on the speed of the IOC's task.
        features: the features the IOC may weigh.
    """

    name: str
    description: str
    demo_speed: float = NOMINAL_SPEED
    noise: float = 0.0
    ioc_leg_mass: float = 1.0
    ioc_speed: float = 1.0
    features: tuple[str, ...] = COST_FEATURES

    def demo_task(self) -> Task:
        return Task(self.demo_speed)

    def ioc_task(self) -> Task:
        return Task(self.demo_speed * self.ioc_speed)

    def ioc_params(self, truth: WalkerParams) -> WalkerParams:
        return truth if self.ioc_leg_mass == 1.0 else truth.with_leg_mass_scale(self.ioc_leg_mass)


CONDITIONS: dict[str, Condition] = {
    c.name: c
    for c in (
        Condition("ideal", "exact model, task and features"),
        Condition("ideal-fast", "exact, at the fast speed 0.34", demo_speed=FAST_SPEED),
        Condition("noise", "observation + Gaussian noise, sigma 5 % of each signal's span", noise=0.05),
        Condition("mass", "IOC model: legs 10 % heavier, torso lighter", ioc_leg_mass=1.1),
        Condition("speed", "IOC task 10 % faster than the demonstration", ioc_speed=1.1),
        Condition("distractor", "3 distractor features added (true weight 0)", features=ALL_FEATURES),
    )
}


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
