"""Why a kinematics-only fit settles away from the truth: the fit's tracking error against the truth's.

For each case of a suite (default ``random-kinematics``: noise-kinematics on weight sets
drawn from the simplex) and the ``bilevel`` algorithm, it runs the case's IOC as the runner
does (the same demonstration, the same observation noise) and then measures, on the same
problem and with bilevel's own tracking error ``D(w) = |r(w)|^2`` (every forward solve warm
from the observation's projection, so each ``w`` has one optimum in the observation's basin):

- ``D`` at the estimate and at the true weights, each with forward solves straight from the
  projection (``D_*``) and through bilevel's proximal option as well (``D_*_nearer``: the
  straight and a proximal solve, the optimum nearer the observation kept), which reaches the
  demonstrated optimum where the straight solve from a reference with inferred torques does not;
- ``D`` of the demonstrated step itself (the true weights' best optimum of 15 starts, which
  the observation is a noisy copy of): the tracking error no weights can beat but by fitting noise;
- the weight error of the estimate, its status, the forward solves and the seconds.

The reading: where ``D(truth) < D(estimate)``, the truth fits the noisy observation better
and the search stopped in another basin of ``D`` (starts or stopping are to blame); where
``D(estimate) <= D(truth)``, the data prefer the wrong weights (no start can mend that, only
the fit's objective or more data).

    python studies/kinematics_only.py --out F.jsonl [--suite random-kinematics] [--algorithm bilevel]
        [--config '{"proximal": 100}']

One JSON line per case; a summary at the end. Resumable: cases already in ``--out`` are skipped.
"""

from __future__ import annotations

import argparse
import json
import time
from pathlib import Path

import numpy as np

from ioc_bench.ioc.bilevel import BilevelConfig, _error, _Fit
from ioc_bench.ioc.fit import fit
from ioc_bench.synthetic.case import _params, _problem
from ioc_bench.synthetic.demos import demonstration
from ioc_bench.synthetic.suites import get_suite


def demonstration_error(problem, demo) -> float:
    """Bilevel's tracking error of the demonstrated step itself (one trial)."""
    view = problem.forward
    ref, weight = view.tracking_quadratic()
    rows = np.flatnonzero(weight > 0)
    r = np.sqrt(weight[rows]) * (view.vector(demo.trajectory)[rows] - ref[rows])
    return float(r @ r)


def measure(spec, nearer: float) -> dict:
    """One case: the IOC's estimate, and D at the estimate and at the truth."""
    requests = spec.demo_requests(None)
    demos = [demonstration(r) for r in requests]
    problem = _problem(spec, _params(spec, None, demos[0]), demos)
    t0 = time.perf_counter()
    outcome = fit(spec.make_algorithm(), problem)
    seconds = time.perf_counter() - t0
    truth = spec.true_over_features()
    row = {"weight_set": spec.weight_set, "seed": spec.seed, "algorithm": spec.algorithm, "config": spec.config}
    row["seconds"] = seconds
    if outcome.failed:
        return row | {"status": "failed", "reason": outcome.reason}
    w = np.asarray(outcome.result.weights, dtype=float)
    tracking, near = _Fit(problem, BilevelConfig()), _Fit(problem, BilevelConfig(proximal=nearer))
    return row | {
        "status": outcome.result.status,
        "weights": w.round(4).tolist(),
        "true_weights": truth.round(4).tolist(),
        "weight_error": float(np.mean(np.abs(w - truth))),
        "D_estimate": _error(tracking, w),
        "D_truth": _error(tracking, truth),
        "D_estimate_nearer": _error(near, w),
        "D_truth_nearer": _error(near, truth),
        "D_demonstration": demonstration_error(problem, demos[0]),
        "forward_solves": outcome.n_solves,
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, required=True)
    parser.add_argument("--suite", default="random-kinematics")
    parser.add_argument("--algorithm", default="bilevel")
    parser.add_argument("--config", type=json.loads, default={}, help="the algorithm's config (JSON)")
    parser.add_argument("--nearer", type=float, default=100.0, help="the proximal weight of the D_*_nearer solves")
    args = parser.parse_args()
    done = set()
    if args.out.is_file():
        rows = map(json.loads, args.out.read_text().splitlines())
        done = {(r["weight_set"], r["seed"], r["algorithm"], json.dumps(r["config"], sort_keys=True)) for r in rows}
    for spec in get_suite(args.suite).cases(args.algorithm, args.config):
        if (spec.weight_set, spec.seed, spec.algorithm, json.dumps(spec.config, sort_keys=True)) in done:
            continue
        row = measure(spec, args.nearer)
        with args.out.open("a") as f:
            f.write(json.dumps(row) + "\n")
        print(json.dumps(row), flush=True)
    rows = [json.loads(line) for line in args.out.read_text().splitlines()]
    scored = [r for r in rows if "D_truth" in r and r["algorithm"] == args.algorithm]
    stuck = [r for r in scored if r["D_truth"] < r["D_estimate"]]
    print(
        f"{len(scored)} cases: mean weight error {np.mean([r['weight_error'] for r in scored]):.4f}; "
        f"truth fits better than the estimate in {len(stuck)} "
        f"({', '.join(r['weight_set'] for r in stuck) or 'none'})"
    )


if __name__ == "__main__":
    main()
