"""The IOC algorithm interface: a name, a config and ``fit(problem) -> IOCResult``.

The types a plugin builds (:class:`IterationRecord`, :class:`IOCResult`,
:class:`WeightRegion`) are a contract with a version, :data:`API_VERSION`. New fields are
keyword-only, so an argument never changes its meaning; what a plugin written to an
earlier shape passes still means what it meant (see :class:`IterationRecord`, and
``docs/plugin_api.md`` for every shape). Whatever ``fit`` returns is checked at the
boundary (:mod:`ioc_bench.ioc.contract`) before anything reads it.
"""

from __future__ import annotations

import warnings
from dataclasses import asdict, dataclass, field, is_dataclass
from typing import Any, ClassVar

import numpy as np

from ioc_bench.ioc.problem import IOCProblem

#: The shape of the plugin API (what a plugin builds, reads or returns). 1: the first
#: release (``IterationRecord(weights, trajectory_error, solve_status, cost_gap, extra)``);
#: 2: ``IterationRecord(weights, tracking_error, trajectory_error, solve_status, extra)``
#: and the differentiable view; 3: keyword-only additions from here on (``IOCResult``'s
#: ``uncertainty``, multi-trial problems), API 1 records read as API 1 meant them; 4:
#: ``IOCResult``'s ``model_fit`` (:class:`ModelFit`: does the model fit the observation).
API_VERSION = 4

#: Method families (``IOCAlgorithm.family``): ``cutting-plane`` (cuts from forward solves,
#: e.g. the paper's), ``inverse-kkt`` (optimality residual at the observation), ``bilevel``
#: (forward solves fitted to the observation), ``single-level`` (one NLP with the optimality
#: conditions as constraints), ``other``.
FAMILIES = ("cutting-plane", "inverse-kkt", "bilevel", "single-level", "other")

_UNSET: Any = object()


@dataclass(frozen=True, init=False)
class IterationRecord:
    """One iteration of an iterative IOC method: a candidate and its optimal step.

    Make one with :meth:`of` (the errors computed for you), or with keywords::

        IterationRecord(weights, tracking_error=..., trajectory_error=..., solve_status=..., extra={...})

    Positional arguments keep the meaning each API version gave them: API 2's
    ``IterationRecord(weights, tracking_error, trajectory_error, solve_status, extra)`` and
    API 1's ``IterationRecord(weights, trajectory_error, solve_status, cost_gap, extra)``
    (recognised by a text third argument, or by only two arguments; it warns with a
    ``DeprecationWarning``, and ``cost_gap`` goes into ``extra``).

    Attributes:
        weights: (F,) candidate weights (unit norm).
        tracking_error: :meth:`IOCProblem.tracking_error` of the candidate's step (positions,
            velocities and torques, span-normalised), NaN if its solve failed or unknown.
        trajectory_error: the paper's :meth:`IOCProblem.trajectory_error` of that step
            (segment angles and angular velocities), NaN if its solve failed or unknown.
        solve_status: status of the candidate's forward solve.
        extra: algorithm-specific numbers for this iteration (e.g. a cutting-plane method's
            ``cost_gap``), shown as they are.
    """

    weights: tuple[float, ...]
    tracking_error: float
    trajectory_error: float
    solve_status: str
    extra: dict[str, Any]

    def __init__(
        self,
        weights: Any,
        *args: Any,
        tracking_error: Any = _UNSET,
        trajectory_error: Any = _UNSET,
        solve_status: Any = _UNSET,
        extra: Any = _UNSET,
    ):
        given = {"tracking_error": tracking_error, "trajectory_error": trajectory_error}
        given |= {"solve_status": solve_status, "extra": extra}
        for name, value in _positional(args).items():
            if given[name] is not _UNSET:
                raise TypeError(f"IterationRecord got {name} both by position and by keyword")
            given[name] = value
        defaults = {"tracking_error": float("nan"), "trajectory_error": float("nan"), "solve_status": "", "extra": {}}
        object.__setattr__(self, "weights", weights)
        for name, value in given.items():
            object.__setattr__(self, name, defaults[name] if value is _UNSET else value)

    def to_dict(self) -> dict[str, Any]:
        return asdict(self)

    @classmethod
    def of(cls, problem: IOCProblem, weights: np.ndarray, solution: Any, **extra: Any) -> IterationRecord:
        """The record of candidate ``weights`` and its oracle ``solution`` (for a multi-trial
        problem, a sequence of one solution per trial: the mean tracking error and the summed
        trajectory error over trials)."""
        if isinstance(solution, (list, tuple)):
            ok = all(bool(s.success) for s in solution)
            steps = [s.trajectory for s in solution]
            return cls(
                weights=tuple(float(x) for x in weights),
                tracking_error=problem.tracking_error(steps) if ok else float("nan"),
                trajectory_error=problem.trajectory_error(steps) if ok else float("nan"),
                solve_status=", ".join(str(s.status) for s in solution),
                extra=extra,
            )
        ok = bool(solution.success)
        return cls(
            weights=tuple(float(x) for x in weights),
            tracking_error=problem.tracking_error(solution.trajectory) if ok else float("nan"),
            trajectory_error=problem.trajectory_error(solution.trajectory) if ok else float("nan"),
            solve_status=str(solution.status),
            extra=extra,
        )


def _positional(args: tuple) -> dict[str, Any]:
    """The fields positional arguments after ``weights`` stand for, by API version."""
    if not args:
        return {}
    if len(args) > 4:
        raise TypeError(f"IterationRecord takes at most 5 positional arguments, got {len(args) + 1}")
    if len(args) == 1 or isinstance(args[1], str):  # API 1: (trajectory_error, solve_status, cost_gap, extra)
        warnings.warn(
            "IterationRecord(weights, trajectory_error, solve_status, ...) is the API 1 shape; it is read as "
            "API 1 meant it. Use keywords (or IterationRecord.of) from API 3 on.",
            DeprecationWarning,
            stacklevel=3,
        )
        out = dict(zip(("trajectory_error", "solve_status"), args[:2]))
        extra = args[3] if len(args) > 3 else {}
        if len(args) > 2:  # cost_gap was a field of API 1; a malformed extra is left for the boundary check
            out["extra"] = {"cost_gap": args[2]} | extra if isinstance(extra, dict) else extra
        return out
    return dict(zip(("tracking_error", "trajectory_error", "solve_status", "extra"), args))


@dataclass(frozen=True)
class WeightRegion:
    """How sure an estimate is: a region of unit-norm weights with a stated coverage.

    Attributes:
        lower, upper: (F,) per-weight interval of the unit-norm weights (``lower <= upper``).
        level: the coverage the region claims (0.95: it should hold the true weights in 95 %
            of cases; the leaderboard measures whether it does).
        covariance: (F, F) covariance of the unit-norm weights where the method has one.
        method: how it was computed, in a few words.
    """

    lower: tuple[float, ...]
    upper: tuple[float, ...]
    level: float = 0.95
    covariance: tuple[tuple[float, ...], ...] | None = None
    method: str = ""

    def contains(self, weights: np.ndarray) -> bool:
        """Whether every weight lies in its interval."""
        w = np.asarray(weights, dtype=float)
        return bool(np.all(w >= np.asarray(self.lower)) and np.all(w <= np.asarray(self.upper)))

    @property
    def width(self) -> float:
        """Mean interval width over the weights."""
        return float(np.mean(np.asarray(self.upper) - np.asarray(self.lower)))

    def to_dict(self) -> dict[str, Any]:
        return asdict(self)


@dataclass(frozen=True)
class ModelFit:
    """Whether the model fits the observation: the fit's tracking residual tested against the
    noise level estimated from the observation itself.

    A model that can produce the observation leaves a residual of the noise's size; a wrong
    model (a mass or speed error) leaves more. A region computed from the residual's spread
    describes noise around a model, so when the data reject the model the region is
    conditional on a model they reject.

    Attributes:
        rejected: the data reject the model (``statistic > threshold``, as the method judged).
        statistic: the test statistic (the residual's mean square over the estimated noise
            variance: about 1 when the model fits noisy data, below 1 for exact data).
        threshold: the statistic's largest value that still fits.
        noise_level: the estimated noise, a fraction of each measured signal's span.
        tracking_error: the fit's tracking error (mean over trials for several).
        method: how it was tested, in a few words.
    """

    rejected: bool
    statistic: float
    threshold: float
    noise_level: float
    tracking_error: float
    method: str = ""

    def to_dict(self) -> dict[str, Any]:
        return asdict(self)


@dataclass(frozen=True)
class IOCResult:
    """What an algorithm returns.

    Attributes:
        weights: (F,) estimated weights over the problem's features (non-negative).
        status: ``converged``, ``max_iterations``, ``infeasible`` (stopped because no
            weights separate the samples), or ``failed: <reason>``.
        history: per-iteration records (may be empty for non-iterative methods).
        chosen_iteration: index into ``history`` of the output, if any.
        notes: free-form numbers or text the algorithm wants in the record (JSON values).
        uncertainty: a :class:`WeightRegion` saying how sure the estimate is, or None
            (keyword only; API 3).
        model_fit: a :class:`ModelFit` saying whether the model fits the observation, or
            None (keyword only; API 4).
    """

    weights: np.ndarray
    status: str = "converged"
    history: tuple[IterationRecord, ...] = ()
    chosen_iteration: int | None = None
    notes: dict[str, Any] = field(default_factory=dict)
    uncertainty: WeightRegion | None = field(default=None, kw_only=True)
    model_fit: ModelFit | None = field(default=None, kw_only=True)


class IOCAlgorithm:
    """Base class of IOC algorithms.

    Subclasses set ``Config`` (a frozen dataclass with documented defaults) and
    ``description`` (one line), and implement :meth:`fit`. Register them with
    :func:`ioc_bench.register_algorithm`.
    """

    name: ClassVar[str] = ""
    description: ClassVar[str] = ""
    #: The method family, one of :data:`FAMILIES` (the leaderboard compares within a family).
    family: ClassVar[str] = "other"
    #: Whether :meth:`fit` handles a problem with several trials (``problem.trials``); an
    #: algorithm that does not is recorded as failed on such a problem, with that reason.
    multi_trial: ClassVar[bool] = False
    Config: ClassVar[type] = type(None)

    def __init__(self, config: Any = None, **overrides: Any):
        if config is None:
            config = self.Config(**overrides) if self.Config is not type(None) else None
        elif overrides:
            raise TypeError("pass either a config object or keyword overrides, not both")
        self.config = config

    def fit(self, problem: IOCProblem) -> IOCResult:
        raise NotImplementedError

    @classmethod
    def prepare(cls) -> None:
        """Build what every case of this algorithm shares (e.g. a compiled NLP), once per
        process; the runner calls it before forking workers. Default: nothing."""

    def config_dict(self) -> dict[str, Any]:
        return asdict(self.config) if is_dataclass(self.config) else {}
