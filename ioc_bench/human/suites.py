"""The human track's suites as data: which subjects, speeds and designs make up a run.

A :class:`HumanSuite` gives the cases of one algorithm, as the synthetic suites do, so
``ioc-bench run --suite human --algorithm A`` runs it like any suite. A suite names the gait
model its cases map the person's steps to (the walker unless it says otherwise; ``--model``
runs any human suite on another model human steps map to) and the task its walker is given
(the speed only, unless it says the person's step length too) and the cost basis its
algorithm weighs (the effort basis unless it says otherwise).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, replace
from typing import Any

from ioc_bench.bases import DEFAULT_BASIS
from ioc_bench.human.case import HumanCaseSpec
from ioc_bench.human.record import GIVEN_STEP, SPEED_ONLY
from ioc_bench.model.catalogue import DEFAULT_MODEL

#: The shipped subjects and treadmill speeds.
SHIPPED_SUBJECTS: tuple[str, ...] = ("WBDS01", "WBDS02", "WBDS03")
SPEED_CODES: tuple[str, ...] = ("T03", "T04", "T05", "T06")
#: Subjects of the data set that are not shipped, for the generalisation check (two young
#: adults, two older ones whose force files mark the unloaded foot NaN).
UNSHIPPED_SUBJECTS: tuple[str, ...] = ("WBDS04", "WBDS10", "WBDS30", "WBDS40")


@dataclass(frozen=True)
class Design:
    """One training design over the speeds: the training speeds, the predicted ones, and
    whether the cost is fitted on the other subjects (a population design)."""

    train: tuple[str, ...]
    predict: tuple[str, ...]
    population: bool = False

    def case(self, subject: str, subjects: tuple[str, ...], algorithm: str, config: Mapping[str, Any]):
        others = tuple(s for s in subjects if s != subject) if self.population else ()
        return HumanCaseSpec(
            subject, self.train[0], self.predict, algorithm, config=dict(config), also_train=self.train[1:],
            population=others,
        )  # fmt: skip


def one_speed(train: str) -> Design:
    return Design((train,), tuple(s for s in SPEED_CODES if s != train))


#: Every design of the ``human`` suite: each speed alone, two speeds (interpolating and
#: extrapolating), each speed left out, and the population fitted at T05.
DESIGNS: tuple[Design, ...] = (
    *(one_speed(code) for code in SPEED_CODES),
    Design(("T04", "T05"), ("T03", "T06")),
    Design(("T03", "T06"), ("T04", "T05")),
    *(Design(tuple(s for s in SPEED_CODES if s != out), (out,)) for out in ("T03", "T06")),
    Design(("T05",), SPEED_CODES, population=True),
)


@dataclass(frozen=True)
class HumanSuite:
    """Every design of :attr:`designs` for every subject of :attr:`subjects`."""

    name: str
    description: str
    subjects: tuple[str, ...]
    designs: tuple[Design, ...]
    model: str = DEFAULT_MODEL
    task: str = SPEED_ONLY
    basis: str = DEFAULT_BASIS

    @property
    def weight_sets(self) -> tuple[str, ...]:
        return self.subjects

    def cases(
        self, algorithm: str, config: Mapping[str, Any] | None = None, model: str | None = None, data: str | None = None
    ) -> list[HumanCaseSpec]:
        """The suite's cases for ``algorithm`` (``ValueError`` for a bad name or config)."""
        cfg = dict(config or {})
        specs = [d.case(s, self.subjects, algorithm, cfg) for s in self.subjects for d in self.designs]
        return [replace(spec, model=model or self.model, task=self.task, basis=self.basis, data=data) for spec in specs]

    def __len__(self) -> int:
        return len(self.subjects) * len(self.designs)


HUMAN_SUITES: dict[str, HumanSuite] = {
    s.name: s
    for s in (
        HumanSuite(
            "human-smoke",
            "the human track in a minute or two: WBDS01 trained at T05, predicting T04",
            ("WBDS01",),
            (Design(("T05",), ("T04",)),),
        ),
        HumanSuite(
            "human-rolling-feet",
            "the human track's smoke case on the walker with rolling feet and a free knee (the subject's body): "
            "WBDS01 trained at T05, predicting T04",
            ("WBDS01",),
            (Design(("T05",), ("T04",)),),
            model="rolling-feet",
        ),
        HumanSuite(
            "human-unshipped",
            "subjects the package does not ship (needs --data: a WBDS folder): young adults WBDS04, WBDS10, "
            "older adults WBDS30, WBDS40, each trained at T03 and at T05, predicting the other three speeds",
            UNSHIPPED_SUBJECTS,
            (one_speed("T03"), one_speed("T05")),
        ),
        HumanSuite(
            "human",
            "the human track: 3 shipped subjects x 9 training designs (each speed alone, two speeds, "
            "leave one out, population), the walker given the speed only",
            SHIPPED_SUBJECTS,
            DESIGNS,
        ),
        HumanSuite(
            "human-energetics",
            "the human track's cases with the energetics cost basis (the efforts, positive joint work and the "
            "heel-strike collision loss) instead of the effort basis",
            SHIPPED_SUBJECTS,
            DESIGNS,
            basis="energetics",
        ),
        HumanSuite(
            "human-energetics-fits",
            "the energetics cost basis fitted at each shipped subject's T05, predicting T04 and T06: a quick look "
            "at what the richer basis fits and predicts",
            SHIPPED_SUBJECTS,
            (Design(("T05",), ("T04", "T06")),),
            basis="energetics",
        ),
        HumanSuite(
            "human-given-step",
            "the human track's cases with the person's step length given at every speed as well as the speed "
            "(the walker's step length and cadence are then the person's)",
            SHIPPED_SUBJECTS,
            DESIGNS,
            task=GIVEN_STEP,
        ),
    )
}
