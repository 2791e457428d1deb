"""Projections of perturbed observations: started cold at the perturbed values, or warm at the reference.

``log-barrier`` seeds its suboptimal set with ``n_random`` projections of 5 % perturbations
of the observation (``ioc_bench.ioc.cutting_plane``). Each is a tracking NLP whose target
is a small perturbation of the observation, whose own projection (the reference) is
already solved. This measures, per observation, both starts of the same projections:
IPOPT iterations and seconds (medians over the samples), whether both converged, and
the largest relative difference of the projected steps' features (the same optimum or not).

Usage::

    python benchmarks/projection_starts.py                       # 4 weight sets x ideal, noise
    python benchmarks/projection_starts.py --samples 10 --noise 0.05

The demonstrations are single-start (seed 0), not the benchmark's 15-start ones.
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from ioc_bench.features import COST_FEATURES
from ioc_bench.ioc.problem import IOCProblem
from ioc_bench.optimize import optimize_gait
from ioc_bench.synthetic.observe import observe
from ioc_bench.weights import WEIGHT_SETS


def _timed(fn, *args, **kwargs):
    t0 = time.perf_counter()
    out = fn(*args, **kwargs)
    return out, time.perf_counter() - t0


def measure(weight_set: str, noise: float, samples: int, perturbation: float) -> dict:
    """Both starts of ``samples`` projections of perturbations of one observation."""
    demo = optimize_gait(weight_set, starts=1, seed=0, workers=1, verify=False)
    observed = observe(demo.trajectory, noise, np.random.default_rng(0))
    problem = IOCProblem(observed, COST_FEATURES, demo.params, demo.task, seed=0)
    reference, rng = problem.reference(), problem.rng(stream=1)
    rows = []
    for _ in range(samples):
        target = problem.perturb(rng, perturbation)
        cold, t_cold = _timed(problem.project, target)
        warm, t_warm = _timed(problem.project, target, start=reference)
        both = cold.success and warm.success
        diff = np.max(np.abs(warm.features - cold.features) / np.abs(cold.features)) if both else np.nan
        rows.append((cold.report.iterations, warm.report.iterations, t_cold, t_warm, both, diff))
    it_c, it_w, t_c, t_w, ok, diff = (np.array(col) for col in zip(*rows))
    return {
        "iterations": (np.median(it_c), np.median(it_w)),
        "seconds": (np.median(t_c), np.median(t_w)),
        "converged": int(ok.sum()),
        "max_feature_diff": float(np.nanmax(diff)) if ok.any() else float("nan"),
    }


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--samples", type=int, default=10, help="projections per observation (default 10)")
    ap.add_argument("--noise", type=float, default=0.05, help="the noisy observation's noise (default 0.05)")
    ap.add_argument("--perturbation", type=float, default=0.05, help="the samples' noise (default 0.05)")
    args = ap.parse_args()
    print("| weight set | observation | iterations cold / warm | s cold / warm | both converged | max feature diff |")
    print("|---|---|---|---|---|---|")
    for name in WEIGHT_SETS:
        for label, noise in (("ideal", 0.0), (f"noise {args.noise:g}", args.noise)):
            m = measure(name, noise, args.samples, args.perturbation)
            (ic, iw), (tc, tw) = m["iterations"], m["seconds"]
            print(
                f"| {name} | {label} | {ic:.0f} / {iw:.0f} | {tc:.2f} / {tw:.2f} | "
                f"{m['converged']}/{args.samples} | {m['max_feature_diff']:.1e} |",
                flush=True,
            )


if __name__ == "__main__":
    main()
