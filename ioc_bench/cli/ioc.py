"""``ioc-bench ioc``: run one IOC case, print its score, write its result and convergence plot.

The result is written to ``--out`` (default ``ioc_result.json`` in the current folder) and its
plot beside it. Exit code 0 when the case ran, 1 when it failed (the algorithm raised or
returned something the plugin contract does not allow: the record is written all the same,
with the reason, the time and the solves spent), 2 on bad input (nothing is run).
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from ioc_bench.cli.common import (
    UsageError,
    add_json_flag,
    add_model_arg,
    check_cache,
    json_object,
    model_weights,
    output_file,
    path_arg,
    print_json,
    seed_int,
    usage_errors,
    weights_arg,
)


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("ioc", help="run one IOC case and score it", description=__doc__)
    p.add_argument("--algorithm", default="log-barrier", help="registered algorithm (see `ioc-bench algorithms`)")
    p.add_argument("--weights", type=weights_arg, default="nominal", help="true weights: set name or hip,knee,dtau")
    p.add_argument("--condition", default="ideal", help="robustness condition (default ideal)")
    add_model_arg(p)
    p.add_argument("--seed", type=seed_int, default=0, help="seed of the algorithm and of observation noise (>= 0)")
    config_help = "algorithm config overrides as JSON, e.g. '{\"n_random\": 5}'"
    p.add_argument("--config", type=json_object, default={}, help=config_help)
    p.add_argument(
        "--out",
        type=path_arg,
        default=Path("ioc_result.json"),
        help="result file (JSON; default ioc_result.json); plot beside it",
    )
    add_json_flag(p)
    p.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    from ioc_bench.fileio import atomic_write_json
    from ioc_bench.synthetic.case import run_spec
    from ioc_bench.viz.convergence import plot_convergence

    spec, algo = _case(args)
    if args.out.suffix == ".png":
        raise UsageError(f"--out {args.out} names the JSON result; its plot is written beside it as .png")
    output_file(args.out)
    output_file(args.out.with_suffix(".png"), "--out (its plot)")
    check_cache()
    if not args.json:
        print(
            f"running {spec.algorithm} on {spec.weight_set} weights of the {spec.model}, {spec.condition} condition, "
            f"seed {spec.seed}",
            file=sys.stderr,
        )
    result = run_spec(spec, algo=algo)  # the algorithm built above, not again
    atomic_write_json(args.out, result.to_dict())
    plot = plot_convergence(result, args.out.with_suffix(".png"))
    summary = result.to_dict() | {"iterations": len(result.history), "result_file": str(args.out), "plot": str(plot)}
    if args.json:
        print_json(summary)
    else:
        _print(result, summary)
    return 1 if result.failed else 0


def _case(args: argparse.Namespace):
    """The case and its algorithm, each resolved once from the arguments (bad input: exit 2,
    before any work): the model, then the weights on it, the condition, the algorithm."""
    from ioc_bench.ioc.registry import make_algorithm
    from ioc_bench.model.catalogue import get_model
    from ioc_bench.synthetic.case import CaseSpec
    from ioc_bench.synthetic.conditions import get_condition

    model = get_model(args.model)
    model_weights(args.weights, model)
    with usage_errors():
        condition = get_condition(args.condition)
        algo = make_algorithm(args.algorithm, **args.config)  # the name and every config field
        return CaseSpec(args.algorithm, args.weights, condition, args.seed, args.config, model), algo


def _print(result, summary: dict) -> None:
    for i, h in enumerate(result.history):
        w = " ".join(f"{x:.4f}" for x in h.get("weights", ()))
        mark = "  <- output" if i == result.chosen_iteration else ""
        gap = ""
        if isinstance(h.get("cost_gap"), (int, float)):
            gap = f"  cost gap {h['cost_gap']:+.2e} ({'cut' if h['cost_gap'] < 0 else 'no cut'})"
        err = h.get("trajectory_error")
        err_text = f"{err:.3g}" if isinstance(err, (int, float)) else "n/a"
        print(f"  iter {i:2d}  w = [{w}]  traj. error {err_text}{gap}{mark}")
    names = ", ".join(result.features)
    fmt = lambda v: "[" + ", ".join(f"{x:.4f}" for x in v) + "]"  # noqa: E731
    print(f"status          {result.status}" + (f" ({result.reason})" if result.reason else ""))
    print(f"weights ({names})  estimated {fmt(result.weights)}  true {fmt(result.true_weights)}")
    print(f"weight error    {result.weight_error:.5f}")
    print(f"trajectory err. {result.trajectory_error:.4g}")
    region = result.uncertainty
    if region is not None:
        held = "holds" if result.covered else "does not hold"
        rejected = " (conditional on a model the data reject)" if result.misfit else ""
        print(f"95 % region     lower {fmt(region['lower'])}  upper {fmt(region['upper'])}: {held} the truth{rejected}")
    if result.model_fit is not None:
        fit = result.model_fit
        verdict = "the data reject the model" if fit["rejected"] else "the model fits"
        print(
            f"model fit       {verdict}: residual statistic {fit['statistic']:.3g} (threshold {fit['threshold']:.3g}; "
            f"estimated noise {fit['noise_level']:.2g} of span)"
        )
    moved = result.transfer
    if moved is not None:
        scored = isinstance(moved.get("trajectory_error"), (int, float))
        score = f"traj. error {moved['trajectory_error']:.3g}, excess cost {moved['excess_cost']:.3g}" if scored else ""
        print(f"transfer        at speed {moved['speed']:g}: {score or moved['status']}")
    print(f"cost            {result.n_solves} forward solves, {result.wall_time:.1f} s")
    print(f"wrote           {summary['result_file']} and {summary['plot']}")
