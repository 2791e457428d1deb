"""The paper's iterative IOC recast as an analytic-centre cutting-plane method (ACCPM).

Why the printed method stalls on this walker (measured; see docs/ioc.md):

1. Features are 1e-4..1e-6, so ``log(1.5 + w . d)`` is linear in ``w`` to 1e-5: the weight
   step is a linear program whose optimum sits on an edge of the cone of separating
   weights, not inside it, so each new cut removes little.
2. A forward solve under candidate weights, even started from x*, often ends in a local
   optimum that costs *more* than x* under those weights (the knee-lock makes the cost
   landscape rugged). Its features then satisfy the candidate's own constraint, the
   sample adds no cut, and the same weights come back.

This variant fixes both, keeping the paper's structure (samples, weight optimization,
forward solves, iterate):

- the weight step is the analytic centre of the cone of separating weights, in features
  scaled by their observed values, so every cut goes through the middle of what is left;
- the forward step is a proximal solve anchored at x*: minimise ``w.phi(x)/w.phi(x*) +
  lambda * D(x, x*)``. Started at x* and held near it, it comes back cheaper under ``w``
  whenever ``w`` is not optimal for x*, which is a cut (and, x* being locally optimal for the
  true weights, a cut that keeps them); if it returns x* itself, ``w`` is consistent with
  the observation. ``lambda`` rises through a ladder until a cut is found;
- it stops when no cut is found at the largest ``lambda`` or the weights stop moving, and
  outputs the last centre. Known limit: IPOPT can still wander off and return a costlier
  step, which this rule also reads as "no cut" (seen once in the ablation, docs/ioc.md);
- when the observation is infeasible for the IOC's model (noise, wrong mass or speed), it
  works around the observation's feasible projection x^ instead (x^ = x* when x* is
  feasible);
- if the cuts become inconsistent (no weights make x^ optimal: an imperfect observation,
  or an x* that IPOPT left stationary but not minimal across a knee-lock switch), it
  stops and outputs the centre of the cone relaxed just enough to be non-empty (1.5x the
  smallest relaxation). Measured on the two fast-gait cases where this happens: the last
  feasible centre gave 0.005 and 0.019, the max-min weights 0.029 and 0.005.
"""

from __future__ import annotations

from dataclasses import dataclass

from ioc_bench.ioc.log_barrier import LogBarrier, LogBarrierConfig
from ioc_bench.ioc.registry import register_algorithm


@dataclass(frozen=True)
class AnalyticCenterConfig(LogBarrierConfig):
    """:class:`LogBarrierConfig` with every fix on (see the module docstring)."""

    n_random: int = 0
    max_iterations: int = 40
    weight_tol: float = 2e-4
    lower: float = 0.0
    upper: float = 1.0
    objective: str = "center"
    scale_features: bool = True
    forward: str = "proximal"
    stop_without_cut: bool = True
    reference: str = "feasible"
    output: str = "last"


@register_algorithm("analytic-center")
class AnalyticCenter(LogBarrier):
    """Log-barrier IOC as an analytic-centre cutting-plane method with proximal cuts."""

    description = "log-barrier IOC as an analytic-centre cutting-plane method (scaled features, proximal cuts)"
    Config = AnalyticCenterConfig
