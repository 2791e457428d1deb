"""IPOPT's settings and statuses, defined once for every NLP ioc-bench solves.

The forward problem (cold and warm-started solves), the single-level IOC NLP and the
weight optimization all build their options from :data:`BASE`; a solve counts as converged
when its status is one of :data:`CONVERGED`.
"""

from __future__ import annotations

from typing import Any

#: Statuses that count as converged (to IPOPT's tolerances or its acceptable ones).
CONVERGED = ("Solve_Succeeded", "Solved_To_Acceptable_Level")

#: Quiet output and no bound relaxation. Relaxed by 1e-8, idle lock torques sat at -1e-8
#: where the knee was flexed, the lock penalty rewarded it (2e-5 of objective at a
#: demonstration) and a projection of a demonstration onto itself stopped 1e-8 away; the
#: weight optimization's logarithms need iterates inside their bounds too.
BASE: dict[str, Any] = {
    "ipopt.print_level": 0,
    "ipopt.sb": "yes",
    "print_time": False,
    "ipopt.bound_relax_factor": 0.0,
}

#: MUMPS without its own scaling and with loose pivoting: the transcription's KKT systems
#: are banded and well scaled, and both only slowed each factorization down (2-3x measured).
MUMPS: dict[str, Any] = {
    "ipopt.mumps_scaling": 0,
    "ipopt.mumps_permuting_scaling": 0,
    "ipopt.mumps_pivtol": 1e-8,
}

#: Start exactly at a given primal-dual point (no push away from the bounds), with a small
#: barrier: for solves that begin at, or next to, a solution.
WARM_START: dict[str, Any] = {
    "ipopt.warm_start_init_point": "yes",
    "ipopt.mu_init": 1e-6,
    "ipopt.warm_start_bound_push": 1e-9,
    "ipopt.warm_start_bound_frac": 1e-9,
    "ipopt.warm_start_slack_bound_push": 1e-9,
    "ipopt.warm_start_slack_bound_frac": 1e-9,
    "ipopt.warm_start_mult_bound_push": 1e-9,
}


def converged(status: str) -> bool:
    """Whether an IPOPT return status means it converged."""
    return status in CONVERGED


def options(*parts: dict[str, Any], **overrides: Any) -> dict[str, Any]:
    """:data:`BASE` merged with ``parts`` and ``ipopt.<key>`` overrides (later ones win)."""
    out = dict(BASE)
    for part in parts:
        out |= part
    return out | {f"ipopt.{k}": v for k, v in overrides.items()}
