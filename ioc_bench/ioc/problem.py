"""What an IOC algorithm is given: an observation, a feature set, and counted oracles.

An :class:`IOCProblem` holds the observed step (possibly noisy), the features the IOC may
weigh (possibly with distractors) and the model and task the IOC *believes* in (possibly
wrong). Algorithms reach the walker only through its oracles:

- :meth:`IOCProblem.optimize`: the optimal step for candidate weights (forward solve);
- :meth:`IOCProblem.project`: the feasible step closest to an arbitrary one;
- :meth:`IOCProblem.features_of`: feature values of a step.

Every oracle call is counted and timed. The true weights are not in the problem: the
observation carries no weights, features or solver data of the demonstration.
"""

from __future__ import annotations

import time
from collections import Counter
from dataclasses import dataclass, field

import numpy as np

from ioc_bench.features import check_names, evaluate
from ioc_bench.model.params import WalkerParams
from ioc_bench.model.walker import walker_linkage
from ioc_bench.task import Task
from ioc_bench.trajectory import Trajectory
from ioc_bench.trajopt.gait_nlp import OBJECTIVE_SCALE
from ioc_bench.trajopt.solver import FEASIBILITY_TOL, GaitSolver, SolveResult, StartPoint, get_solver
from ioc_bench.weights import full_weights, normalize

#: Projection objective scale. The span-normalised distance is ~1e-3 for 5 % noise and
#: ~1e-2 for a 10 % speed mismatch; scaled up (1e1, 1e3) it outweighed the knee-lock
#: penalty and projections ended with lock products above the tolerance.
PROJECTION_SCALE = 1.0


@dataclass(frozen=True, eq=False)
class OracleSolution:
    """A step returned by an oracle.

    Attributes:
        trajectory: the step.
        features: (F,) its feature values, in the problem's feature order.
        success: the solve converged to a feasible point.
        status: the solver's status string.
        objective: the oracle's objective at the solution (``w . phi`` for ``optimize``).
    """

    trajectory: Trajectory
    features: np.ndarray
    success: bool
    status: str
    objective: float
    _solve: SolveResult | None = field(default=None, repr=False)


@dataclass
class OracleStats:
    """Calls and seconds spent per oracle."""

    calls: Counter = field(default_factory=Counter)
    seconds: Counter = field(default_factory=Counter)

    @property
    def forward_solves(self) -> int:
        """Trajectory optimizations of any kind (``optimize`` and ``project``)."""
        return self.calls["optimize"] + self.calls["project"]

    def to_dict(self) -> dict:
        return {"calls": dict(self.calls), "seconds": dict(self.seconds), "forward_solves": self.forward_solves}


class IOCProblem:
    """One IOC task: recover weights over :attr:`features` from :attr:`observed`.

    Args:
        observed: the observed step (the IOC's only view of the demonstration).
        features: names of the features the IOC may weigh.
        params: the walker model the IOC believes in.
        task: the task the IOC believes in.
        seed: seed for the algorithm's random choices (use :meth:`rng`).
    """

    def __init__(
        self,
        observed: Trajectory,
        features: tuple[str, ...],
        params: WalkerParams,
        task: Task,
        seed: int = 0,
        solver: GaitSolver | None = None,
    ):
        self.features = check_names(features)
        self.params = params
        self.task = task
        self.seed = seed
        self._solver = solver or get_solver(_intervals(observed))
        if observed.n_knots != self._solver.nlp.n_knots:
            raise ValueError(
                f"observed step has {observed.n_knots} knots, the IOC solver uses {self._solver.nlp.n_knots}"
            )
        self.observed = observed
        self.stats = OracleStats()
        self._linkage = walker_linkage(params)
        self._spans = _signal_spans(observed)

    @property
    def n_features(self) -> int:
        return len(self.features)

    def rng(self, stream: int = 0) -> np.random.Generator:
        """A generator seeded from the problem's seed (``stream`` separates independent uses)."""
        return np.random.default_rng([self.seed, stream])

    # -- oracles ------------------------------------------------------------------------
    def optimize(
        self,
        weights: np.ndarray,
        start: OracleSolution | Trajectory | None = None,
        proximal: float = 0.0,
        anchor: Trajectory | None = None,
    ) -> OracleSolution:
        """The optimal step for ``weights`` under the IOC's model and task.

        Args:
            weights: (F,) non-negative weights over :attr:`features` (normalised here).
            start: an :class:`OracleSolution` (warm primal-dual start), a trajectory (its
                values as the initial guess) or None (start from the observed step).
            proximal: if > 0, minimise ``w.phi(x) / w.phi(anchor) + proximal * D(x, anchor)``
                instead, with ``D`` the span-normalised mean squared distance of
                :meth:`trajectory_error`: a proximal step meant to stay in the anchor's
                basin. Started at the anchor it normally returns a step no costlier than
                the anchor under ``w``, but IPOPT can still wander: check the result.
            anchor: the proximal term's centre (default: the observed step).
        """
        unit_w = normalize(weights)
        w = full_weights(unit_w, self.features)
        ref = track = None
        if proximal > 0:
            anchor = anchor or self.observed
            cost = float(unit_w @ self.features_of(anchor))
            ref, track = self._tracking(anchor, OBJECTIVE_SCALE * proximal * cost)
        with self._timed("optimize"):
            result = self._solver.solve(self._start(start), self.params, self.task.speed, w, ref=ref, track=track)
        return self._wrap(result)

    def project(self, target: Trajectory) -> OracleSolution:
        """The feasible step closest to ``target`` in positions, velocities and torques.

        Each signal's squared error is divided by its span in the observed step, so every
        signal counts alike.
        """
        ref, track = self._tracking(target, PROJECTION_SCALE)
        with self._timed("project"):
            result = self._solver.solve(
                StartPoint(self._solver.decision_vector(target)),
                self.params,
                self.task.speed,
                np.zeros(6),
                ref,
                track,
            )
        return self._wrap(result)

    def is_feasible(self, trajectory: Trajectory, tol: float = FEASIBILITY_TOL) -> bool:
        """Whether a step satisfies the IOC's model and task constraints to ``tol``."""
        with self._timed("feasibility"):
            return self._solver.violation_of(trajectory, self.params, self.task.speed) <= tol

    def features_of(self, trajectory: Trajectory) -> np.ndarray:
        """(F,) feature values of a step, in :attr:`features` order."""
        with self._timed("features"):
            values = evaluate(trajectory, self._linkage, self.features)
        return np.array([values[f] for f in self.features])

    # -- helpers for algorithms ---------------------------------------------------------
    def trajectory_error(self, trajectory: Trajectory) -> float:
        """Mean squared difference to the observed step over positions, velocities and
        torques, each signal divided by its span in the observed step (dimensionless)."""
        diff = (trajectory.signals() - self.observed.signals()) / self._spans
        return float(np.mean(diff**2))

    def perturb(self, rng: np.random.Generator, size: float) -> Trajectory:
        """The observed step plus Gaussian noise of ``size`` times each signal's span."""
        return add_noise(self.observed, rng, size, self._spans)

    # -- internals ----------------------------------------------------------------------
    def _tracking(self, target: Trajectory, strength: float) -> tuple[np.ndarray, np.ndarray]:
        """Reference and weights of ``strength * trajectory_error(x, target)``."""
        ref = target.signals()
        return ref, np.broadcast_to(strength / (self._spans**2 * ref.size), ref.shape)

    def _start(self, start: OracleSolution | Trajectory | None) -> StartPoint:
        if isinstance(start, OracleSolution) and start._solve is not None:
            s = start._solve
            return StartPoint(s.x, s.lam_x, s.lam_g)
        traj = start.trajectory if isinstance(start, OracleSolution) else (start or self.observed)
        return StartPoint(self._solver.decision_vector(traj))

    def _wrap(self, result: SolveResult) -> OracleSolution:
        return OracleSolution(
            trajectory=result.trajectory,
            features=self.features_of(result.trajectory),
            success=result.report.success,
            status=result.report.status,
            objective=result.report.objective,
            _solve=result,
        )

    def _timed(self, name: str):
        return _Timer(self.stats, name)


class _Timer:
    def __init__(self, stats: OracleStats, name: str):
        self.stats, self.name = stats, name

    def __enter__(self) -> None:
        self.t0 = time.perf_counter()

    def __exit__(self, *exc: object) -> None:
        self.stats.calls[self.name] += 1
        self.stats.seconds[self.name] += time.perf_counter() - self.t0


def _intervals(traj: Trajectory) -> int:
    return (traj.n_knots - 1) // 2


def _signal_spans(traj: Trajectory) -> np.ndarray:
    """(n,) span (max - min) of every tracked signal, floored to stay positive."""
    sig = traj.signals()
    span = sig.max(axis=0) - sig.min(axis=0)
    return np.maximum(span, 1e-3 * max(float(span.max()), 1e-12))


def add_noise(traj: Trajectory, rng: np.random.Generator, size: float, spans: np.ndarray | None = None) -> Trajectory:
    """``traj`` with Gaussian noise (sigma = ``size`` x each signal's span) on positions,
    velocities and torques; the other fields are kept."""
    spans = _signal_spans(traj) if spans is None else spans
    t = traj.n_knots
    noisy = traj.signals() + rng.normal(0.0, 1.0, size=(t, spans.size)) * size * spans
    nq = traj.q[0].size
    arrays = traj.to_arrays()
    arrays["q"] = noisy[:, :nq].reshape(traj.q.shape)
    arrays["v"] = noisy[:, nq : 2 * nq].reshape(traj.v.shape)
    arrays["tau"] = noisy[:, 2 * nq :]
    return Trajectory.from_arrays(arrays)
