"""What an IOC algorithm is given: an observation, a feature set, and counted oracles.

An :class:`IOCProblem` holds the observed step (what a lab measures: knot times, segment
positions and velocities, joint torques, possibly noisy, possibly without torques), the
features the IOC may weigh (possibly with distractors) and the model and task the IOC
*believes* in (possibly wrong). Algorithms reach the walker only through it:

- black-box oracles: :meth:`IOCProblem.optimize` (the optimal step for candidate weights),
  :meth:`IOCProblem.project` (the feasible step closest to a given one),
  :meth:`IOCProblem.features_of`, :meth:`IOCProblem.is_feasible`;
- a differentiable view of the forward problem, :attr:`IOCProblem.forward`
  (:class:`~ioc_bench.ioc.forward_view.ForwardView`: constraint Jacobians, feature
  gradients and Hessians, duals and the sensitivity of an optimum to the weights);
- metrics: :meth:`IOCProblem.tracking_error` and :meth:`IOCProblem.trajectory_error`.

Every oracle and derivative call is counted and timed. The true weights are not in the
problem, nor anything the observation does not contain (accelerations, constraint forces,
lock torques, impulses, solver data).
"""

from __future__ import annotations

import hashlib
import json
import numbers
import time
from collections.abc import Sequence
from dataclasses import replace
from functools import cached_property
from typing import Protocol

import numpy as np

from ioc_bench.bases import forward_basis
from ioc_bench.features import check_model_names, evaluate
from ioc_bench.ioc.forward_view import ForwardView
from ioc_bench.ioc.oracle import OracleSolution, OracleStats
from ioc_bench.ioc.smoothing import LADDER as SMOOTHING_LADDER
from ioc_bench.ioc.smoothing import NOISE_FLOOR, discrepancy_target, noise_level
from ioc_bench.metrics import trajectory_error
from ioc_bench.model.catalogue import model_of
from ioc_bench.model.gait_model import GaitModel, GaitParams
from ioc_bench.task import Task
from ioc_bench.trajectory import Observation, Trajectory
from ioc_bench.trajopt.forward_problem import SolveRequest, get_forward_problem
from ioc_bench.trajopt.initial_guess import multistart_guesses
from ioc_bench.trajopt.solution import FEASIBILITY_TOL, SolveResult, SolverReport, StartPoint
from ioc_bench.trajopt.step_problem import OBJECTIVE_SCALE
from ioc_bench.trajopt.tracking import signal_spans, tracking_error, tracking_terms
from ioc_bench.validation import check_non_negative
from ioc_bench.weights import full_weights, normalize

__all__ = ["IOCProblem", "MultiTrialProblem", "OracleSolution", "OracleStats"]

#: Projection objective scale. The span-normalised distance is ~1e-3 for 5 % noise and
#: ~1e-2 for a 10 % speed mismatch; scaled up (1e1, 1e3) it outweighed the knee-lock
#: penalty and projections ended with lock products above the tolerance.
PROJECTION_SCALE = 1e4
#: Most starts one ``optimize`` call may ask for (each is a counted forward solve).
MAX_STARTS = 100


#: Key of :attr:`OracleStats.seconds` holding the seconds a stored reference took when it
#: was computed (charged to the problem that reuses it, so times stay comparable).
REUSED_REFERENCE = "reused_reference"


class ReferenceStore(Protocol):
    """Somewhere references are kept between problems: by key, the reference's primal-dual
    point, its solver report, how many projections it took and their seconds."""

    def get(self, key: str) -> tuple[StartPoint, SolverReport, int, float] | None: ...

    def put(self, key: str, point: StartPoint, report: SolverReport, solves: int, seconds: float) -> None: ...


class IOCProblem:
    """One IOC task: recover weights over :attr:`features` from :attr:`observed`.

    To experiment outside ``run_case``, build one from a demonstration (the benchmark's
    own measurement model is :func:`ioc_bench.synthetic.observe.observe`)::

        demo = ioc_bench.optimize_gait("penalize-knee", starts=1)
        problem = IOCProblem(demo.trajectory, ("hip", "knee", "dtau"), demo.params, demo.task)

    Args:
        observed: the observed step (the IOC's only view of the demonstration; a full
            :class:`Trajectory` is reduced to what is measured of it).
        features: names of the features the IOC may weigh: any the model has
            (:func:`~ioc_bench.features.available_features`; those outside its default basis,
            such as ``work``, are added to the forward problem's basis).
        params: the model parameters the IOC believes in.
        task: the task the IOC believes in.
        seed: seed for the algorithm's random choices (use :meth:`rng`).
        model: the gait model (keyword only; default: the one whose parameters ``params``
            are, e.g. the walker for :class:`~ioc_bench.model.params.WalkerParams`).
        reference_store: where the reference (:meth:`reference`) may be read from or kept
            (keyword only; the benchmark shares one per machine, so algorithms and scoring
            of one observation project it once). A stored reference still counts the
            projections it took, and their seconds in ``stats.seconds["reused_reference"]``.

    Raises:
        ValueError: an argument of the wrong type or shape, a feature the model lacks.
    """

    def __init__(
        self,
        observed: Observation,
        features: Sequence[str],
        params: GaitParams,
        task: Task,
        seed: int = 0,
        *,
        model: GaitModel | None = None,
        reference_store: ReferenceStore | None = None,
    ):
        if not isinstance(observed, Observation):
            raise ValueError(f"observed must be an Observation or a Trajectory, got {type(observed).__name__}")
        if isinstance(observed, Trajectory):
            observed = observed.observed()  # never hand an algorithm the solver's hidden variables
        if not isinstance(task, Task):
            raise ValueError(f"task must be a Task, got {type(task).__name__}")
        if not isinstance(seed, numbers.Integral) or isinstance(seed, bool) or seed < 0:
            raise ValueError(f"seed must be an integer >= 0, got {seed!r}")
        self.model = model or model_of(params)
        if not isinstance(params, type(self.model.default_params)):
            raise ValueError(f"params must be {type(self.model.default_params).__name__} for model {self.model.name!r}")
        self.features = check_model_names(self.model, tuple(features))
        self.params, self.task, self.seed = params, task, int(seed)
        basis = forward_basis(self.model, self.features)
        self._forward = get_forward_problem(self.model, (observed.n_knots - 1) // 2, basis)
        n_act = len(self._forward.actuators)
        if observed.q.shape[1:] != (len(self._forward.step.seg_names), 3):
            raise ValueError(
                f"observed positions have shape {observed.q.shape[1:]} per knot, model {self.model.name!r} "
                f"has {len(self._forward.step.seg_names)} segments"
            )
        if observed.tau is not None and observed.tau.shape[1] != n_act:
            raise ValueError(f"observed torques have {observed.tau.shape[1]} columns, the model has {n_act}")
        self.observed = observed
        self.stats = OracleStats()
        self.reference_store = reference_store
        self._spans = signal_spans(observed, n_act)

    @property
    def n_features(self) -> int:
        return len(self.features)

    @property
    def trials(self) -> tuple[IOCProblem, ...]:
        """The observed trials: this problem alone (a :class:`MultiTrialProblem` has several)."""
        return (self,)

    @property
    def signal_spans(self) -> np.ndarray:
        """(n,) span of every measured signal of the observed step (what the tracking error
        divides each difference by; 1 for signals not measured)."""
        return self._spans.copy()

    def rng(self, stream: int = 0) -> np.random.Generator:
        """A generator seeded from the problem's seed (``stream`` separates independent uses)."""
        return np.random.default_rng([self.seed, stream])

    @cached_property
    def forward(self) -> ForwardView:
        """The differentiable view of the forward problem (built on first use)."""
        return ForwardView(self._forward, self.features, self.params, self.task, self.observed, self._spans, self.stats)

    # -- oracles ------------------------------------------------------------------------
    def optimize(
        self,
        weights: np.ndarray,
        start: OracleSolution | Trajectory | None = None,
        proximal: float = 0.0,
        anchor: Observation | None = None,
        starts: int = 1,
    ) -> OracleSolution:
        """The optimal step for ``weights`` under the IOC's model and task.

        Args:
            weights: (F,) non-negative weights over :attr:`features` (normalised here).
            start: an :class:`OracleSolution` (a warm primal-dual start: the solve begins
                exactly there), a :class:`Trajectory` (its values as a cold initial guess) or
                None (warm from :meth:`reference`, the projected observation).
            proximal: if > 0, minimise ``w.phi(x) / w.phi(anchor) + proximal * D(x, anchor)``
                instead, with ``D`` the :meth:`tracking_error`: a proximal step meant to
                stay in the anchor's basin. Started at the anchor it normally returns a step
                no costlier than the anchor under ``w``, but IPOPT can still wander: check.
            anchor: the proximal term's centre (default: the observed step; its projection
                if the observation has no torques).
            starts: also solve from ``starts - 1`` rough periodic guesses with noise (the
                paper's multi-start, seeded from the problem's seed) and keep the cheapest
                feasible result. Every solve counts as a forward solve.
        """
        if not isinstance(starts, numbers.Integral) or isinstance(starts, bool) or not 1 <= starts <= MAX_STARTS:
            raise ValueError(f"starts must be an integer in 1..{MAX_STARTS}, got {starts!r}")
        check_non_negative(proximal, "proximal")
        unit_w = normalize(weights)
        if unit_w.size != self.n_features:
            raise ValueError(f"expected {self.n_features} weights ({', '.join(self.features)}), got {unit_w.size}")
        w = full_weights(unit_w, self.features, self._forward.features)
        tracking = None
        if proximal > 0:
            if anchor is None:
                anchor = self.observed if self.observed.tau is not None else self.reference().trajectory
            cost = float(unit_w @ self.features_of(anchor))
            tracking = tracking_terms(anchor, OBJECTIVE_SCALE * proximal * cost, self._spans)
        points = [self._start(start), *self._guesses(int(starts) - 1)]
        results = []
        for point in points:
            with self.stats.timed("optimize"):
                results.append(self._forward.solve(SolveRequest(point, self.params, self.task, w, tracking)))
        feasible = [r for r in results if r.report.success]
        best = min(feasible, key=lambda r: r.report.objective) if feasible else results[0]
        return self._wrap(best, unit_w)

    def project(self, target: Observation, start: OracleSolution | None = None) -> OracleSolution:
        """The feasible step closest to ``target`` in its measured positions, velocities and
        torques (each signal's squared error divided by its span in the observed step).

        Args:
            target: the step to project, of the observed step's knots.
            start: a projection to start from, warm (its primal-dual point), e.g.
                :meth:`reference` for a small perturbation of the observation; default:
                ``target``'s own values as a cold guess.
        """
        if not isinstance(target, Observation) or target.n_knots != self.observed.n_knots:
            raise ValueError(f"target must be an Observation of {self.observed.n_knots} knots, like problem.observed")
        if start is not None and (not isinstance(start, OracleSolution) or start.point is None):
            raise ValueError("start must be an OracleSolution with its primal-dual point (e.g. problem.reference())")
        tracking = tracking_terms(target, PROJECTION_SCALE, self._spans)
        zeros = np.zeros(len(self._forward.features))
        start = start.point if start is not None else StartPoint(self._forward.guess_vector(target, self.params))
        with self.stats.timed("project"):
            result = self._forward.solve(SolveRequest(start, self.params, self.task, zeros, tracking))
        return self._wrap(result, np.zeros(self.n_features))

    @cached_property
    def noise_level(self) -> float:
        """The observation's noise, estimated from the observation itself (a fraction of each
        measured signal's span; :func:`~ioc_bench.ioc.smoothing.noise_level`)."""
        return noise_level(self.observed.signals(len(self._forward.actuators)))

    @cached_property
    def _reference(self) -> OracleSolution:
        stored = self.reference_store.get(self._reference_key) if self.reference_store else None
        if stored is not None and not self._fits(stored[0]):
            stored = None  # not a point of this problem: computed again (and the entry replaced)
        if stored is not None:
            point, report, solves, seconds = stored
            self.stats.calls["project"] += solves  # the projections it took, counted as if made here
            self.stats.seconds[REUSED_REFERENCE] += seconds  # and their time, charged by the caller
            return self._wrap(
                SolveResult(self._forward.trajectory(point.x, self.params), report, point.x, point.lam_x, point.lam_g),
                np.zeros(self.n_features),
            )
        before, t0 = self.stats.calls["project"], time.perf_counter()
        plain = self.project(self.observed)
        if not plain.success:
            plain = self._projected_again(plain)
        found = plain if self.noise_level <= NOISE_FLOOR or not plain.success else self._smoothed(plain)
        if self.reference_store is not None and found.point is not None and found.report is not None:
            solves = self.stats.calls["project"] - before
            self.reference_store.put(self._reference_key, found.point, found.report, solves, time.perf_counter() - t0)
        return found

    def _projected_again(self, failed: OracleSolution) -> OracleSolution:
        """A failed projection of the observation retried from a feasible step: the optimum
        for uniform weights, started where the projection stopped, then the projection warm
        from it. ``failed`` if either solve fails. (On ``rolling-feet`` observations a cold
        projection can end in restoration failure where this converges; ``docs/feet.md``.)"""
        forward = self.optimize(np.ones(self.n_features), start=failed)
        if not forward.success or forward.point is None:
            return failed
        again = self.project(self.observed, start=forward)
        return again if again.success else failed

    def _fits(self, point: StartPoint) -> bool:
        """Whether a stored primal-dual point has this problem's shape and satisfies its constraints."""
        f = self._forward
        shapes = (point.x.shape, point.lam_x.shape, point.lam_g.shape) == ((f.n_x,), (f.n_x,), (f.n_g,))
        return shapes and bool(np.all(np.isfinite(point.x))) and self.is_feasible(f.trajectory(point.x, self.params))

    @cached_property
    def _reference_key(self) -> str:
        """What the reference depends on: the observation, the model, its parameters and the task."""
        digest = hashlib.sha256()
        digest.update(np.ascontiguousarray(self.observed.signals(len(self._forward.actuators))).tobytes())
        digest.update(np.float64(self.observed.dt).tobytes())
        payload = {
            "params": self.params.to_dict(),
            "speed": self.task.speed,
            "step_length": self.task.step_length,
            "model": self.model.name,
            "knots": self.observed.n_knots,
            "ladder": list(SMOOTHING_LADDER),
        }
        digest.update(json.dumps(payload, sort_keys=True).encode())
        return digest.hexdigest()[:24]

    def reference(self) -> OracleSolution:
        """The feasible reference of the observation, computed on first use: its projection
        (one projection) if the observation is exact; for a noisy one, the projection smoothed
        just enough not to fit the noise (:mod:`ioc_bench.ioc.smoothing`; each smoothing
        solve counts as a projection)."""
        return self._reference

    def _smoothed(self, plain: OracleSolution) -> OracleSolution:
        """The smoothest projection (of the ladder) within the discrepancy target."""
        target = discrepancy_target(self.tracking_error(plain.trajectory), self.noise_level)
        best, start = plain, plain.point
        for mu in SMOOTHING_LADDER:
            tracking = replace(
                tracking_terms(self.observed, PROJECTION_SCALE, self._spans), smoothing=mu * PROJECTION_SCALE
            )
            zeros = np.zeros(len(self._forward.features))
            with self.stats.timed("project"):
                result = self._forward.solve(SolveRequest(start, self.params, self.task, zeros, tracking))
            if not result.report.success or self.tracking_error(result.trajectory) > target:
                break
            best = self._wrap(result, np.zeros(self.n_features))
            start = result.point
        return best

    def is_feasible(self, trajectory: Trajectory, tol: float = FEASIBILITY_TOL) -> bool:
        """Whether a full trajectory satisfies the IOC's model and task constraints to ``tol``."""
        if not isinstance(trajectory, Trajectory):
            raise TypeError("is_feasible needs a full Trajectory (an observation lacks forces): project it first")
        with self.stats.timed("feasibility"):
            return self._forward.violation_of(trajectory, self.params, self.task) <= tol

    def features_of(self, step: Observation) -> np.ndarray:
        """(F,) feature values of a step (an observation with torques, or a trajectory)."""
        if not isinstance(step, Observation) or step.tau is None:
            raise ValueError(
                "features_of needs a step with torques (an oracle solution's trajectory, or an observation)"
            )
        with self.stats.timed("features"):
            values = evaluate(step, self.params, self.features, self.model)
        return np.array([values[f] for f in self.features])

    # -- metrics and helpers for algorithms ---------------------------------------------
    def tracking_error(self, step: Observation) -> float:
        """Mean squared difference to the observed step over its measured positions,
        velocities and torques, each signal divided by its span in the observed step."""
        return tracking_error(step, self.observed, self._spans)

    def trajectory_error(self, step: Observation) -> float:
        """The paper's trajectory error to the observed step: sum over knots and segments of
        squared segment-angle and angular-velocity differences."""
        return trajectory_error(step, self.observed)

    def perturb(self, rng: np.random.Generator, size: float) -> Observation:
        """The observed step plus Gaussian noise of ``size`` times each measured signal's span."""
        sig = self.observed.signals(len(self._forward.actuators))
        noisy = sig + rng.normal(0.0, 1.0, size=sig.shape) * size * self._spans
        return self.observed.with_signals(noisy)

    # -- internals ----------------------------------------------------------------------
    def _start(self, start: OracleSolution | Trajectory | None) -> StartPoint:
        if start is None:
            start = self.reference()
        if isinstance(start, OracleSolution) and start.point is not None:
            return start.point
        traj = start.trajectory if isinstance(start, OracleSolution) else start
        if not isinstance(traj, Trajectory):
            raise ValueError("start must be an OracleSolution, a Trajectory or None; project an observation first")
        return StartPoint(self._forward.vector(traj))

    def _guesses(self, n: int) -> list[StartPoint]:
        if n <= 0:
            return []
        fwd = self._forward
        tried = multistart_guesses(self.model, self.params, self.task.speed, None, fwd.n_knots, n, self.seed)
        return [StartPoint(fwd.step.layout.pack(blocks)) for _, blocks in tried]

    def _wrap(self, result: SolveResult, weights: np.ndarray) -> OracleSolution:
        return OracleSolution(
            trajectory=result.trajectory,
            features=self.features_of(result.trajectory),
            success=result.report.success,
            status=result.report.status,
            objective=result.report.objective,
            weights=weights,
            point=result.point,
            report=result.report,
        )


class MultiTrialProblem:
    """Several observed trials of one subject, to be explained by one weight vector.

    The paper's further work: "IOC can estimate a cost function for multiple trials,
    limiting the effects of noise and variability". Each trial is an :class:`IOCProblem`
    with its own observation and task (e.g. one per speed) under one model and feature set;
    their oracle calls are counted together in :attr:`stats`. An algorithm that handles
    several trials declares ``multi_trial = True`` and iterates over :attr:`trials`; any
    other is recorded as failed on such a problem, with that reason.

    Args:
        trials: the trials (at least two; the same features, model and seed).
    """

    def __init__(self, trials: Sequence[IOCProblem]):
        trials = tuple(trials)
        if len(trials) < 2 or not all(isinstance(t, IOCProblem) for t in trials):
            raise ValueError("a multi-trial problem needs two or more IOCProblem trials")
        first = trials[0]
        if any(t.features != first.features or t.model is not first.model for t in trials):
            raise ValueError("every trial of a multi-trial problem must have the same features and model")
        self.trials = trials
        self.features, self.model, self.seed = first.features, first.model, first.seed
        self.stats = OracleStats()
        for trial in trials:
            trial.stats = self.stats  # one count for the whole problem

    @property
    def n_features(self) -> int:
        return len(self.features)

    def rng(self, stream: int = 0) -> np.random.Generator:
        """A generator seeded from the problem's seed (``stream`` separates independent uses)."""
        return np.random.default_rng([self.seed, stream])

    def tracking_error(self, steps: Sequence[Observation]) -> float:
        """The mean over trials of each trial's tracking error of its step."""
        return float(np.mean([t.tracking_error(s) for t, s in zip(self.trials, steps, strict=True)]))

    def trajectory_error(self, steps: Sequence[Observation]) -> float:
        """The sum over trials of the paper's trajectory error of each trial's step."""
        return float(np.sum([t.trajectory_error(s) for t, s in zip(self.trials, steps, strict=True)]))
