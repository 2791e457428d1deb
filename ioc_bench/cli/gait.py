"""``ioc-bench gait``: optimize one step, print its features, save it and its plot."""

from __future__ import annotations

import argparse
from pathlib import Path

from ioc_bench.cli.common import (
    add_json_flag,
    add_model_arg,
    add_multistart_args,
    model_weights,
    output_file,
    path_arg,
    print_json,
    progress_bar,
    solver_dict,
    weights_arg,
)
from ioc_bench.task import NOMINAL_SPEED


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("gait", help="optimize the walking step for given weights", description=__doc__)
    p.add_argument("--weights", type=weights_arg, default="nominal", help="weight set name or numbers hip,knee,dtau")
    add_model_arg(p)
    add_multistart_args(p, NOMINAL_SPEED)
    p.add_argument("--out", type=path_arg, default=Path("demo.npz"), help="demonstration file to write (.npz)")
    p.add_argument("--no-plot", action="store_true", help="skip the stick-figure plot")
    add_json_flag(p)
    p.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    from ioc_bench.model.catalogue import get_model
    from ioc_bench.optimize import optimize_gait
    from ioc_bench.task import Task

    model = get_model(args.model)
    weights = model_weights(args.weights, model)
    out = output_file(args.out if args.out.suffix == ".npz" else args.out.with_suffix(".npz"))
    if not args.no_plot:
        output_file(out.with_suffix(".png"), "--out (its plot)")
    with progress_bar(args.starts, "multi-start", enabled=not args.json) as bar:
        demo = optimize_gait(
            weights,
            task=Task(args.speed),
            model=model,
            starts=args.starts,
            seed=args.seed,
            workers=args.workers,
            on_start_done=lambda done, total: bar.update(1),
        )
    demo.save(out)
    plot = None
    if not args.no_plot:
        from ioc_bench.viz.gait_plot import plot_gait

        plot = plot_gait(demo, out.with_suffix(".png"))
    report = {
        "weights": demo.weights,
        "speed": demo.task.speed,
        "features": demo.features,
        "gait": demo.gait.to_dict() if demo.gait else None,
        "warnings": demo.gait.warnings if demo.gait else [],
        "local_minimum": demo.local_minimum.to_dict() if demo.local_minimum else None,
        "solver": solver_dict(demo.solver),
        "multistart": demo.multistart.describe() if demo.multistart else None,
        "optima": demo.multistart.optima if demo.multistart else None,
        "out": str(out),
        "plot": None if plot is None else str(plot),
    }
    if args.json:
        print_json(report)
    else:
        _print_report(report)
    return 0 if demo.solver.success else 1


def _print_report(r: dict) -> None:
    w = ", ".join(f"{k}={v:.3f}" for k, v in r["weights"].items() if v)
    print(f"weights  {w}   speed {r['speed']:g}")
    g = r["gait"]
    if g:
        print(
            f"step     length {g['step_length']:.3f} L, duration {g['duration']:.3f}; with a 0.9 m leg: "
            f"{g['step_length_m']:.2f} m at {g['cadence']:.0f} steps/min, {g['speed_mps']:.2f} m/s"
        )
        print(
            f"swing    foot clearance max {g['max_clearance']:.3f} L, mid-swing min {g['mid_swing_clearance']:.4f} L; "
            "peak |torque| " + ", ".join(f"{k} {v:.3f}" for k, v in g["peak_torques"].items())
        )
        physical = ", ".join(f"{k} x{n}" for k, n in g["active"].get("physical", {}).items()) or "none"
        print(f"bounds   active (physical): {physical}")
    for warning in r["warnings"]:
        print(f"warning  {warning}")
    check = r["local_minimum"]
    if check:
        verdict = "local minimum" if check["passed"] else "NOT VERIFIED as a local minimum"
        print(
            f"check    {verdict}: proximal descents found at most {check['largest_decrease']:.1e} relative decrease "
            f"(tolerance {check['tolerance']:g}); polished {check['rounds']} time(s), by {check['polished_by']:.1e}"
        )
    print("features " + "  ".join(f"{k}={v:.4e}" for k, v in r["features"].items()))
    s = r["solver"]
    ok = "feasible" if s["success"] else "NOT FEASIBLE"
    print(
        f"solver   {s['status']} ({ok}), max violation {s['max_violation']:.1e}, "
        f"{s['iterations']} iterations, {s['wall_time']:.2f} s"
    )
    if r["multistart"]:
        print(f"starts   {r['multistart']}")
    print(f"wrote    {r['out']}" + (f" and {r['plot']}" if r["plot"] else ""))
