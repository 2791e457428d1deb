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

import numbers
from collections.abc import Sequence
from functools import cached_property

import numpy as np

from ioc_bench.features import check_names, evaluate, model_features
from ioc_bench.ioc.forward_view import ForwardView
from ioc_bench.ioc.oracle import OracleSolution, OracleStats
from ioc_bench.metrics import trajectory_error
from ioc_bench.model.catalogue import model_of
from ioc_bench.model.gait_model import GaitModel, GaitParams
from ioc_bench.task import Task
from ioc_bench.trajectory import Observation, Trajectory
from ioc_bench.trajopt.forward_problem import SolveRequest, get_forward_problem
from ioc_bench.trajopt.initial_guess import multistart_guesses
from ioc_bench.trajopt.solution import FEASIBILITY_TOL, SolveResult, StartPoint
from ioc_bench.trajopt.step_problem import OBJECTIVE_SCALE
from ioc_bench.trajopt.tracking import signal_spans, tracking_error, tracking_terms
from ioc_bench.weights import full_weights, normalize

__all__ = ["IOCProblem", "OracleSolution", "OracleStats"]

#: Projection objective scale. The span-normalised distance is ~1e-3 for 5 % noise and
#: ~1e-2 for a 10 % speed mismatch; scaled up (1e1, 1e3) it outweighed the knee-lock
#: penalty and projections ended with lock products above the tolerance.
PROJECTION_SCALE = 1e4
#: Most starts one ``optimize`` call may ask for (each is a counted forward solve).
MAX_STARTS = 100


class IOCProblem:
    """One IOC task: recover weights over :attr:`features` from :attr:`observed`.

    To experiment outside ``run_case``, build one from a demonstration (the benchmark's
    own measurement model is :func:`ioc_bench.bench.observe.observe`)::

        demo = ioc_bench.optimize_gait("penalize-knee", starts=1)
        problem = IOCProblem(demo.trajectory, ("hip", "knee", "dtau"), demo.params, demo.task)

    Args:
        observed: the observed step (the IOC's only view of the demonstration; a full
            :class:`Trajectory` is reduced to what is measured of it).
        features: names of the features the IOC may weigh (the model's).
        params: the model parameters the IOC believes in.
        task: the task the IOC believes in.
        seed: seed for the algorithm's random choices (use :meth:`rng`).
        model: the gait model (keyword only; default: the one whose parameters ``params``
            are, e.g. the walker for :class:`~ioc_bench.model.params.WalkerParams`).

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
        self.features = check_names(tuple(features))
        missing = [f for f in self.features if f not in model_features(self.model)]
        if missing:
            raise ValueError(f"model {self.model.name!r} has no feature(s) {missing}")
        self.params, self.task, self.seed = params, task, int(seed)
        self._forward = get_forward_problem(self.model, (observed.n_knots - 1) // 2)
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
        self._spans = signal_spans(observed, n_act)

    @property
    def n_features(self) -> int:
        return len(self.features)

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
        if not (isinstance(proximal, numbers.Real) and np.isfinite(proximal) and proximal >= 0):
            raise ValueError(f"proximal must be a finite number >= 0, got {proximal!r}")
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

    def project(self, target: Observation) -> OracleSolution:
        """The feasible step closest to ``target`` in its measured positions, velocities and
        torques (each signal's squared error divided by its span in the observed step)."""
        if not isinstance(target, Observation) or target.n_knots != self.observed.n_knots:
            raise ValueError(f"target must be an Observation of {self.observed.n_knots} knots, like problem.observed")
        tracking = tracking_terms(target, PROJECTION_SCALE, self._spans)
        zeros = np.zeros(len(self._forward.features))
        start = StartPoint(self._forward.guess_vector(target, self.params))
        with self.stats.timed("project"):
            result = self._forward.solve(SolveRequest(start, self.params, self.task, zeros, tracking))
        return self._wrap(result, np.zeros(self.n_features))

    @cached_property
    def _reference(self) -> OracleSolution:
        return self.project(self.observed)

    def reference(self) -> OracleSolution:
        """The projected observation (computed on first use, counted as one projection)."""
        return self._reference

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
