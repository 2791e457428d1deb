"""The paper's iterative IOC recast as an analytic-centre cutting-plane method (ACCPM).

Why the printed method stalls on this walker, measured in ``docs/ioc.md``: its weight step
is nearly linear, so each candidate sits on an edge of the cone of separating weights, and
a plain forward solve often ends in another local optimum that costs *more* than x* under
the candidate, so the sample adds no cut and the same weights come back. This composition
of :mod:`ioc_bench.ioc.cutting_plane`'s strategies keeps the paper's structure and changes:

- the reference: the observation's feasible projection x^ (x* itself when the IOC's model
  can produce it);
- the weight step: the analytic centre of the cone of separating weights, in features
  scaled by their value at x^, so every cut goes through the middle of what is left; if
  the cuts become inconsistent, the centre of the cone relaxed just enough to be non-empty;
- the forward step: a proximal solve anchored at x^, ``min w.phi(x)/w.phi(x^) + lambda
  D(x, x^)``, ``lambda`` rising through a ladder until the step is cheaper than x^ (a cut;
  x* being locally optimal for the true weights, such cuts keep them);
- no random samples; stop when no cut is found (the candidate is consistent with x^);
  output the last centre.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import partial

import numpy as np

from ioc_bench.ioc.algorithm import IOCAlgorithm, IOCResult
from ioc_bench.ioc.cutting_plane import AnalyticCentreStep, CuttingPlane, ProximalForward, ReferenceChoice, last_output
from ioc_bench.ioc.problem import IOCProblem
from ioc_bench.ioc.registry import register_algorithm


@dataclass(frozen=True)
class AnalyticCenterConfig:
    """Settings of the analytic-centre cutting-plane method.

    Attributes:
        max_iterations: candidates tried at most.
        weight_tol: stop when no weight (unit norm) moves more than this.
        lower: lower bound of every weight (the paper's method uses 0.001).
        proximal: the ladder of proximal weights of the forward step.
        cut_threshold: relative cost decrease (and feature difference) below which a step is
            x^ again, not a cut.
        n_random: projected random perturbations seeding the samples (they cut little).
        perturbation: their noise, as a fraction of each signal's span.
    """

    max_iterations: int = 40
    weight_tol: float = 2e-4
    lower: float = 0.0
    proximal: tuple[float, ...] = (30.0, 300.0)
    cut_threshold: float = 1e-6
    n_random: int = 0
    perturbation: float = 0.05

    def __post_init__(self) -> None:
        if self.max_iterations < 1 or self.n_random < 0 or not (0 <= self.lower < 1):
            raise ValueError("max_iterations must be >= 1, n_random >= 0 and 0 <= lower < 1")
        if not self.proximal or any(p <= 0 for p in self.proximal):
            raise ValueError("proximal must be a non-empty ladder of positive weights")
        if not (self.weight_tol >= 0 and self.cut_threshold >= 0 and self.perturbation > 0):
            raise ValueError("weight_tol and cut_threshold must be >= 0, perturbation > 0")
        object.__setattr__(self, "proximal", tuple(self.proximal))


def _centre_step(lower: float, phi_ref: np.ndarray) -> AnalyticCentreStep:
    unit = np.maximum(phi_ref, 1e-3 * phi_ref.max())
    return AnalyticCentreStep(unit, lower=lower)


@register_algorithm("analytic-center")
class AnalyticCenter(IOCAlgorithm):
    """Log-barrier IOC as an analytic-centre cutting-plane method with proximal cuts."""

    description = "log-barrier IOC as an analytic-centre cutting-plane method (scaled features, proximal cuts)"
    family = "cutting-plane"
    multi_trial = True
    Config = AnalyticCenterConfig

    def fit(self, problem: IOCProblem) -> IOCResult:
        cfg: AnalyticCenterConfig = self.config
        return CuttingPlane(
            reference=ReferenceChoice("projected"),
            weight_step=partial(_centre_step, cfg.lower),
            forward=ProximalForward(cfg.proximal),
            output=last_output,
            n_random=cfg.n_random,
            perturbation=cfg.perturbation,
            max_iterations=cfg.max_iterations,
            weight_tol=cfg.weight_tol,
            cut_threshold=cfg.cut_threshold,
            stop_without_cut=True,
        ).run(problem)
