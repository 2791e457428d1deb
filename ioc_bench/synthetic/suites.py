"""Benchmark suites as data: which weight sets, conditions and seeds make up a run.

Add a suite by adding a :class:`Suite` to :data:`SUITES` (or :func:`register_suite`); the
track hands :data:`SUITES` to the runner (:mod:`ioc_bench.synthetic.track`), which finds
every track's suites by name.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

from ioc_bench.bases import DEFAULT_BASIS, get_basis
from ioc_bench.features import cost_features
from ioc_bench.model.catalogue import ANKLE_FEET, COMPASS, DEFAULT_MODEL, ROLLING_FEET, get_model
from ioc_bench.synthetic.case import CaseSpec
from ioc_bench.synthetic.conditions import AXES, axis_conditions, get_condition, lookup, register
from ioc_bench.validation import check_seed
from ioc_bench.weights import WEIGHT_SETS, simplex_weight_sets, weight_sets


@dataclass(frozen=True)
class Suite:
    """A grid of cases: every weight set under every condition, once per seed, on one model."""

    name: str
    description: str
    weight_sets: tuple[str, ...]
    conditions: tuple[str, ...]
    seeds: tuple[int, ...] = (0,)
    model: str = DEFAULT_MODEL
    basis: str = DEFAULT_BASIS

    def __post_init__(self) -> None:
        gait_model = get_model(self.model)
        for w in self.weight_sets:
            get_basis(self.basis).parse_weights(w, gait_model)
        for c in self.conditions:
            get_condition(c)
        if not self.seeds:
            raise ValueError(f"suite {self.name!r} needs at least one seed")
        for seed in self.seeds:
            check_seed(seed, f"suite {self.name!r} seed")

    def __len__(self) -> int:
        return len(self.weight_sets) * len(self.conditions) * len(self.seeds)

    def cases(
        self, algorithm: str, config: Mapping[str, Any] | None = None, model: str | None = None
    ) -> list[CaseSpec]:
        """The suite's cases for ``algorithm``, in a fixed order, on the suite's model or ``model``
        (``ValueError`` for a bad name, config, or a weight set the model lacks)."""
        cfg = dict(config or {})
        return [
            CaseSpec(algorithm, w, c, s, cfg, model or self.model, self.basis)
            for s in self.seeds
            for c in self.conditions
            for w in self.weight_sets
        ]


#: The seed of the random-kinematics suite's weight sets.
RANDOM_WEIGHTS_SEED = 2026

#: The paper's conditions (``docs/spec.md``, "Conditions"), and the torque-free reading of its noise.
PAPER_CONDITIONS = ("ideal", "ideal-fast", "noise", "noise-kinematics", "mass", "speed", "distractor")
#: The paper's further work: several trials of one subject (both speeds) for one cost.
MULTI_TRIAL_CONDITIONS = ("multi-speed", "multi-speed-noise")
#: Every condition on the robustness axes (ideal once), by axis then severity.
#: The basis of the energetics suites.
ENERGETICS = get_basis("energetics")
ROBUSTNESS_CONDITIONS = tuple(dict.fromkeys(c.name for axis in AXES for c in axis_conditions(axis)))

SUITES: dict[str, Suite] = {
    s.name: s
    for s in (
        Suite(
            "smoke",
            "a quick check (minutes): two weight sets, ideal and noisy observations",
            weight_sets=("nominal", "penalize-knee"),
            conditions=("ideal", "noise"),
        ),
        Suite(
            "paper",
            "the paper's study: 4 weight sets x its 6 conditions, noise-kinematics and two multi-trial ones, one seed",
            weight_sets=tuple(WEIGHT_SETS),
            conditions=PAPER_CONDITIONS + MULTI_TRIAL_CONDITIONS,
        ),
        Suite(
            "ideal",
            "exact model, task and features at both speeds: 4 weight sets x ideal, ideal-fast",
            weight_sets=tuple(WEIGHT_SETS),
            conditions=("ideal", "ideal-fast"),
        ),
        Suite(
            "unseen",
            "ideal condition on weight sets no algorithm was tuned on",
            weight_sets=("3,1,5", "1,4,2", "2,2,1", "5,2,1"),
            conditions=("ideal",),
        ),
        Suite(
            "random-kinematics",
            "noise-kinematics (angles and rates only, as people are observed) on 12 weight sets drawn uniformly "
            f"from the simplex (seed {RANDOM_WEIGHTS_SEED})",
            weight_sets=simplex_weight_sets(12, RANDOM_WEIGHTS_SEED),
            conditions=("noise-kinematics",),
        ),
        Suite(
            "paper-3seeds",
            "the paper's study with 3 seeds (each re-solves the demonstration, redraws noise and randomness)",
            weight_sets=tuple(WEIGHT_SETS),
            conditions=PAPER_CONDITIONS + MULTI_TRIAL_CONDITIONS,
            seeds=(0, 1, 2),
        ),
        Suite(
            "compass-smoke",
            "the compass walker (rigid legs, hip torques): a quick check, two weight sets, ideal and noisy",
            weight_sets=("nominal", "penalize-hip"),
            conditions=("ideal", "noise"),
            model=COMPASS.name,
        ),
        Suite(
            "compass-paper",
            "the paper's study on the compass walker: its 3 weight sets x the paper's conditions, one seed",
            weight_sets=tuple(weight_sets(cost_features(COMPASS))),
            conditions=PAPER_CONDITIONS,
            model=COMPASS.name,
        ),
        Suite(
            "rolling-feet-smoke",
            "the walker with rolling feet and a free knee: a quick check, two weight sets, ideal and noisy",
            weight_sets=("nominal", "penalize-knee"),
            conditions=("ideal", "noise"),
            model=ROLLING_FEET.name,
        ),
        Suite(
            "rolling-feet-paper",
            "the paper's study on the walker with rolling feet and a free knee: 4 weight sets x the paper's conditions",
            weight_sets=tuple(weight_sets(cost_features(ROLLING_FEET))),
            conditions=PAPER_CONDITIONS,
            model=ROLLING_FEET.name,
        ),
        Suite(
            "ankle-feet-ideal",
            "the walker with feet on actuated ankles and a free knee, exact: its 5 weight sets (nominal, each of hip, "
            "knee, ankle, dtau penalised) x ideal",
            weight_sets=tuple(weight_sets(cost_features(ANKLE_FEET))),
            conditions=("ideal",),
            model=ANKLE_FEET.name,
        ),
        Suite(
            "ankle-feet-effort-work-ideal",
            "the effort-work cost basis on the walker with feet on actuated ankles, exact: its 6 weight sets "
            "(nominal, each of hip, knee, ankle, dtau, work penalised) x ideal",
            weight_sets=tuple(get_basis("effort-work").weight_sets(ANKLE_FEET)),
            conditions=("ideal",),
            model=ANKLE_FEET.name,
            basis="effort-work",
        ),
        Suite(
            "energetics-ideal",
            "the energetics cost basis (efforts, positive joint work, heel-strike collision loss), exact: its 6 "
            "weight sets (nominal, each feature penalised) x ideal",
            weight_sets=tuple(ENERGETICS.weight_sets(get_model(DEFAULT_MODEL))),
            conditions=("ideal",),
            basis=ENERGETICS.name,
        ),
        Suite(
            "effort-work-ideal",
            "the effort-work cost basis (efforts and positive joint work), exact: its 5 weight sets (nominal, each "
            "feature penalised) x ideal",
            weight_sets=tuple(get_basis("effort-work").weight_sets(get_model(DEFAULT_MODEL))),
            conditions=("ideal",),
            basis="effort-work",
        ),
        Suite(
            "energetics-distractor",
            "the effort basis's 4 weight sets with work and the collision loss offered as well (true weight 0): "
            "does each family keep them at zero?",
            weight_sets=tuple(WEIGHT_SETS),
            conditions=("distractor-energetics",),
        ),
        Suite(
            "robustness",
            "weight error against severity: noise 0-10 %, leg mass and speed errors -20..+20 % (4 weight sets)",
            weight_sets=tuple(WEIGHT_SETS),
            conditions=ROBUSTNESS_CONDITIONS,
        ),
    )
}


def register_suite(suite: Suite) -> Suite:
    return register(SUITES, suite, "suite")


def get_suite(name: str) -> Suite:
    return lookup(SUITES, name, "suite")
