"""Is a step a local minimum of its own cost? A proximal descent says, and polishes it if not.

IPOPT returns stationary points; across a knee-lock switch such a point can be a saddle
or a kink, not a minimum (measured on a fast-gait demonstration: a proximal step
under its own weights found a 0.23 % cheaper step, so an IOC cut removed the truth). The
check minimises ``w . phi(x) + lambda * J(x*) * D(x, x*)`` from ``x*`` for a ladder of
proximal weights ``lambda`` (:mod:`ioc_bench.trajopt.tracking`): a local minimum comes back
to itself. It then probes the neighbourhood beyond the ridge of its basin: proximal steps
from ``x*`` under randomly perturbed weights, each re-solved under ``w``. (Measured: a
demonstration that passed the descent was 0.1 % costlier, under its own weights, than the
optimum such a probe reached, so an IOC cut correctly removed its true weights.) Whenever a
cheaper step is found it is re-solved without the proximal term and the check repeats
from there.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Iterator
from dataclasses import asdict, dataclass, replace
from typing import Any

import numpy as np

from ioc_bench.trajopt.forward_problem import ForwardProblem, SolveRequest
from ioc_bench.trajopt.solution import SolveResult
from ioc_bench.trajopt.step_problem import OBJECTIVE_SCALE
from ioc_bench.trajopt.tracking import signal_spans, tracking_terms

#: Proximal weights tried from each candidate, strongest (smallest move) first.
PROXIMAL_LADDER = (10.0, 1.0, 0.1)
#: A proximal step cheaper than the candidate by more than this (relative) is a cheaper step.
DECREASE_TOL = 1e-6
#: Polishing rounds at most (each takes a cheaper step and checks again).
MAX_ROUNDS = 6
#: Probes beyond the basin: proximal steps under weights perturbed by this (log-normal sigma).
PROBES = 6
PROBE_SPREAD = 0.5
#: The probes' proximal weight.
PROBE_PROXIMAL = 30.0


@dataclass(frozen=True)
class LocalMinimumCheck:
    """The outcome of :func:`verify_local_minimum`, stored with every demonstration.

    Attributes:
        passed: no proximal descent from the final step found one cheaper by more than
            ``tolerance`` (relative).
        largest_decrease: the largest relative cost decrease the final round's descents and
            probes found (<= ``tolerance`` when passed; may be negative: all came back costlier).
        rounds: polishing rounds that found, and moved to, a cheaper step.
        polished_by: total relative cost decrease from the solver's step to the final one.
        proximal: the proximal weights tried.
        tolerance: the relative decrease that counts as cheaper.
        probes: proximal steps under perturbed weights tried per round.
    """

    passed: bool
    largest_decrease: float
    rounds: int
    polished_by: float
    proximal: tuple[float, ...] = PROXIMAL_LADDER
    tolerance: float = DECREASE_TOL
    probes: int = PROBES

    def to_dict(self) -> dict[str, Any]:
        return asdict(self)

    @classmethod
    def from_dict(cls, data: dict[str, Any]) -> LocalMinimumCheck:
        fields = dict(data)
        fields["proximal"] = tuple(fields.get("proximal", PROXIMAL_LADDER))
        return cls(**fields)


def verify_local_minimum(
    forward: ForwardProblem, result: SolveResult, request: SolveRequest
) -> tuple[SolveResult, LocalMinimumCheck]:
    """Check (and polish) a feasible solve of ``request``; returns the final solve and the check."""
    start_cost = result.report.objective
    current = result
    for rounds in range(MAX_ROUNDS + 1):
        cheaper, largest = _descend(forward, current, request)
        if cheaper is None:
            cheaper, probed = _probe(forward, current, request, rounds)
            largest = max(largest, probed)
        if cheaper is None:  # no descent found a cheaper step (unverified if none succeeded)
            polished_by = (start_cost - current.report.objective) / abs(start_cost)
            return current, LocalMinimumCheck(math.isfinite(largest), largest, rounds, polished_by)
        if rounds == MAX_ROUNDS:
            break
        again = forward.solve(replace(request, start=cheaper.point, tracking=None))
        current = again if again.report.success and again.report.objective < cheaper.report.objective else cheaper
    polished_by = (start_cost - current.report.objective) / abs(start_cost)
    return current, LocalMinimumCheck(False, largest, MAX_ROUNDS, polished_by)


def _probe(
    forward: ForwardProblem, current: SolveResult, request: SolveRequest, seed: int
) -> tuple[SolveResult | None, float]:
    """The first probe cheaper than ``current``: a proximal step under perturbed weights,
    re-solved under the request's weights; and the largest relative decrease seen."""
    cost = current.report.objective
    tracking = tracking_terms(current.trajectory, OBJECTIVE_SCALE * PROBE_PROXIMAL * abs(cost), _spans(current))
    rng = np.random.default_rng([seed, 101])
    w = np.asarray(request.weights, dtype=float)

    def probes() -> Iterator[SolveResult]:
        for _ in range(PROBES):
            other = w * np.exp(PROBE_SPREAD * rng.normal(size=w.shape))
            away_request = replace(
                request, start=current.point, weights=other / np.linalg.norm(other), tracking=tracking
            )
            away = forward.solve(away_request)
            if not away.report.success:
                yield away
                continue
            yield forward.solve(replace(request, start=away.point, tracking=None))

    return _first_cheaper(cost, probes())


def _descend(forward: ForwardProblem, current: SolveResult, request: SolveRequest) -> tuple[SolveResult | None, float]:
    """The first proximal step (down the ladder) cheaper than ``current``, and the largest
    relative decrease seen."""
    cost = current.report.objective
    spans = _spans(current)

    def steps() -> Iterator[SolveResult]:
        for lam in PROXIMAL_LADDER:
            tracking = tracking_terms(current.trajectory, OBJECTIVE_SCALE * lam * abs(cost), spans)
            yield forward.solve(replace(request, start=current.point, tracking=tracking))

    return _first_cheaper(cost, steps())


def _spans(result: SolveResult) -> np.ndarray:
    return signal_spans(result.trajectory)


def _first_cheaper(cost: float, solves: Iterable[SolveResult]) -> tuple[SolveResult | None, float]:
    """The first successful solve more than DECREASE_TOL (relative) cheaper than ``cost``,
    solving no further; and the largest relative decrease seen."""
    largest = float("-inf")
    for result in solves:
        if not result.report.success:
            continue
        decrease = (cost - result.report.objective) / abs(cost)
        largest = max(largest, decrease)
        if decrease > DECREASE_TOL:
            return result, largest
    return None, largest
