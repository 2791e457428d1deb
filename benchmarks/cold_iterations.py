"""Which term of the step NLP costs a cold solve its iterations.

A cold solve of the walker's step (speed 0.27, nominal weights, from the rough guesses
``ioc-bench solver-timing`` draws) takes about a hundred IPOPT iterations, and IPOPT
regularises the Hessian of the Lagrangian (its inertia correction) in most of them. This
solves the same starts with terms of the objective switched off, one at a time, and
prints per variant the median iterations, the median number of iterations whose Hessian
was regularised, and the distinct objectives reached:

- ``as built``: the benchmark's NLP;
- ``no lock penalty``: the knee-lock complementarity penalty at 0 (the locks then act as
  free non-negative torques: another problem, measured only to locate the cost);
- ``per-step cost``: the effort summed over the step instead of divided by its duration;
- ``no lock penalty, per-step cost``: both;
- ``lock penalty 0 then 100``: a two-stage solve (the second stage cold from the first's
  optimum), the whole iterations counted.

Usage::

    python benchmarks/cold_iterations.py             # 7 starts per variant
    python benchmarks/cold_iterations.py --starts 3

Iteration counts are deterministic for a given start; seconds are not printed (they depend
on what else the machine runs).
"""

from __future__ import annotations

import argparse
import statistics

import casadi as ca
import numpy as np

from ioc_bench.model.params import WalkerParams
from ioc_bench.model.walker import WALKER
from ioc_bench.task import Task
from ioc_bench.trajopt.forward_problem import COLD_OPTIONS, get_forward_problem
from ioc_bench.trajopt.initial_guess import perturbed_step
from ioc_bench.trajopt.step_problem import LOCK_PENALTY, StepRules
from ioc_bench.weights import full_weights, parse_weights

#: (name, stages): each stage is (lock penalty, cost rule); a later stage starts cold at the
#: previous stage's optimum.
VARIANTS: tuple[tuple[str, tuple[tuple[float, str], ...]], ...] = (
    ("as built", ((LOCK_PENALTY, "per-time"),)),
    ("no lock penalty", ((0.0, "per-time"),)),
    ("per-step cost", ((LOCK_PENALTY, "per-step"),)),
    ("no lock penalty, per-step cost", ((0.0, "per-step"),)),
    ("lock penalty 0 then 100", ((0.0, "per-time"), (LOCK_PENALTY, "per-time"))),
)


def _solve(solver: ca.Function, forward, x0: np.ndarray, penalty: float, cost: str) -> dict:
    params, task = WalkerParams(), Task()
    rules = StepRules(cost=cost)
    w = full_weights(parse_weights("nominal"), forward.features)
    p = forward.parameters(params, task, w, None, penalty, rules)
    lbx, ubx, lbg, ubg = forward.bounds(params, task, rules)
    sol = solver(x0=np.clip(x0, lbx, ubx), p=p, lbx=lbx, ubx=ubx, lbg=lbg, ubg=ubg)
    stats = solver.stats()
    regularised = sum(1 for r in stats["iterations"]["regularization_size"] if r > 0)
    x = np.asarray(sol["x"], dtype=float).ravel()
    return {
        "x": x,
        "status": stats["return_status"],
        "iterations": int(stats["iter_count"]),
        "regularised": regularised,
        "effort": float(forward.step.effort_fn(x, p)),
    }


def measure(starts: int) -> list[dict]:
    """Per variant: median iterations and regularised iterations over ``starts`` starts."""
    forward = get_forward_problem()
    solver = ca.nlpsol("cold_probe", "ipopt", forward.step.casadi_nlp, COLD_OPTIONS)
    guesses = [
        forward.step.layout.pack(
            perturbed_step(WALKER, WalkerParams(), Task().speed, forward.n_knots, np.random.default_rng([1, i]))
        )
        for i in range(starts)
    ]
    rows = []
    for name, stages in VARIANTS:
        its, reg, efforts, failed = [], [], set(), 0
        for x0 in guesses:
            x, total, total_reg = x0, 0, 0
            for penalty, cost in stages:
                out = _solve(solver, forward, x, penalty, cost)
                x, total, total_reg = out["x"], total + out["iterations"], total_reg + out["regularised"]
            its.append(total)
            reg.append(total_reg)
            failed += out["status"] != "Solve_Succeeded"
            efforts.add(round(out["effort"], 7))
        rows.append(
            {
                "variant": name,
                "iterations": statistics.median(its),
                "regularised": statistics.median(reg),
                "range": (min(its), max(its)),
                "failed": failed,
                "efforts": sorted(efforts),
            }
        )
        print(f"{name}: done", flush=True)
    return rows


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--starts", type=int, default=7, help="cold starts per variant (default 7)")
    args = parser.parse_args()
    rows = measure(args.starts)
    header = (
        "variant",
        "iterations: median (range)",
        "regularised iterations: median",
        "failed",
        "weighted effort reached",
    )
    print("| " + " | ".join(header) + " |")
    print("|---" * len(header) + "|")
    for r in rows:
        efforts = ", ".join(f"{e:.7f}" for e in r["efforts"])
        lo, hi = r["range"]
        cells = (r["variant"], f"{r['iterations']:g} ({lo}-{hi})", f"{r['regularised']:g}", str(r["failed"]), efforts)
        print("| " + " | ".join(cells) + " |")


if __name__ == "__main__":
    main()
