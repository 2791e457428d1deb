"""``ioc-bench replay``: check demonstrations in MuJoCo (physical checks; open and closed loop reported).

The verdict is physical, one line per check with its figure and limit: torques consistent
with the dynamics (inverse dynamics), motion consistent with its knot spacing, a stance-foot
ground force that never pulls and stays in the friction cone, no swing foot below the
ground, knees within their range (``envs.checks.physics_checks``). The open loop (the
step under its torques alone) and the closed loop (the gait walked by
``envs.TrackingPolicy`` through the Gymnasium environment's ``step``, the loop users run:
steps walked, feedback share) are reported, not judged: walking is unstable, and a gait
that drifts or needs feedback is unstable, not wrong. Several files are checked one after
the other (``ioc-bench replay demos/*.npz``), with a summary line each; ``--json`` prints
one JSON object per file, one per line.

Exit code 0 when every physical check of every file passes, 1 when one fails, 2 on a
missing or malformed demonstration file (all files are read before any check runs).
``ioc_bench`` does not import ``envs`` (nor MuJoCo) until this command runs.
"""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

from ioc_bench.cli.common import (
    add_json_flag,
    mujoco_log_to_stderr,
    output_dir,
    output_file,
    path_arg,
    positive_int,
    print_json,
    usage_errors,
)

#: MuJoCo models a demonstration can be replayed against.
MODELS = ("demo", "nominal")


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("replay", help="check demonstrations in MuJoCo (physical checks; open/closed loop reported)")
    p.description = __doc__
    p.add_argument(
        "demos", type=path_arg, nargs="+", metavar="DEMO.npz", help="demonstration file(s) written by 'ioc-bench gait'"
    )
    p.add_argument(
        "--out", type=path_arg, default=None, help="directory for the GIFs and plots (default: next to DEMO)"
    )
    p.add_argument("--steps", type=positive_int, default=10, help="closed-loop steps to walk (default 10)")
    p.add_argument(
        "--model",
        choices=MODELS,
        default="demo",
        help="MuJoCo model: the demonstration's own parameters (default) or its gait model's nominal ones",
    )
    p.add_argument("--no-video", action="store_true", help="skip the GIF of the walk")
    add_json_flag(p)
    p.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    from ioc_bench.demo import Demonstration

    demos = []
    for path in args.demos:
        with usage_errors():
            demos.append((path, Demonstration.load(path)))  # every problem with a file is a DemonstrationFileError
    from envs.checks import check_replayable  # lazily: ioc_bench must not need envs (or MuJoCo) to import

    for path, demo in demos:  # every demonstration checked before the first replay
        with usage_errors(f"{path}: "):
            check_replayable(demo)
    if args.out is not None:
        output_dir(args.out)
    for path, _demo in demos:  # every file the replays write, checked before the first replay
        for suffix in ("png",) if args.no_video else ("png", "gif"):
            output_file(_out_dir(path, args) / f"{path.stem}_replay.{suffix}", "--out" if args.out else "replay output")
    mujoco_log_to_stderr()  # never a MUJOCO_LOG.TXT in the current folder
    results = [_replay_one(path, demo, args) for path, demo in demos]
    if not args.json and len(results) > 1:
        _print_summary(results)
    return 0 if all(r["passed"] for r in results) else 1


def _replay_one(path: Path, demo: Any, args: argparse.Namespace) -> dict[str, Any]:
    import envs.checks as checks  # lazily: ioc_bench must not need envs (or MuJoCo) to import
    import envs.plots as plots
    from ioc_bench.model.catalogue import get_model

    params = demo.params if args.model == "demo" else get_model(demo.model).default_params
    report = checks.replay(demo, steps=args.steps, params=params)
    out_dir = _out_dir(path, args)
    stem = path.stem
    outputs = {}
    if report.closed_loop is not None:  # None: the step could not be replayed (report.replay_error)
        plot = plots.plot_comparison(demo, report.open_loop, report.closed_loop, out_dir / f"{stem}_replay.png")
        outputs["plot"] = str(plot)
        if not args.no_video:
            outputs["video"] = str(plots.write_animation(report.closed_loop, params, out_dir / f"{stem}_replay.gif"))
    result = report.to_dict() | {"demo": str(path), "model": args.model, "outputs": outputs}
    if args.json:
        print_json(result)
    else:
        _print_report(result)
    return result


def _out_dir(path: Path, args: argparse.Namespace) -> Path:
    return args.out if args.out is not None else path.parent


def _verdict(passed: bool) -> str:
    return "PASS" if passed else "FAIL"


def _check_line(c: dict[str, Any]) -> str:
    """``name  PASS  quantity value (limit sense limit)``, and the reason of a failure."""
    line = f"{c['name']:<20} {_verdict(c['passed'])}  {c['quantity']} {c['value']:.2e} ({c['sense']} {c['limit']:g})"
    return line if c["passed"] else f"{line}: {c['reason']}"


def _failed_names(r: dict[str, Any]) -> list[str]:
    return [c["name"] for c in r["checks"] if not c["passed"]]


def _print_report(r: dict[str, Any]) -> None:
    print(f"replay   {r['demo']} against the {r['model']} MuJoCo model")
    for c in r["checks"]:
        print(_check_line(c))
    if r["closed_loop"] is None:
        print(f"open and closed loop (not run)  {r['replay_error']}")
    else:
        _print_loops(r["open_loop"], r["closed_loop"])
    failed = _failed_names(r)
    print(f"verdict  {_verdict(r['passed'])}" + (f": {', '.join(failed)}" if failed else ": every physical check"))
    if r["outputs"]:
        print("wrote    " + " and ".join(r["outputs"].values()))


def _print_loops(ol: dict[str, Any], cl: dict[str, Any]) -> None:
    landed = "no landing" if ol["touchdown_time"] is None else f"landed at t={ol['touchdown_time']:.3f}"
    print(
        f"open loop            (reported)  final-state error {ol['final_position_error']:.2e} (positions), "
        f"{ol['final_velocity_error']:.2e} (velocities) after {ol['duration']:.3f}; {landed}"
    )
    fell = "" if cl["fall_reason"] is None else f"; stopped: {cl['fall_reason']}"
    print(
        f"closed loop          (reported)  {cl['steps_walked']}/{cl['steps_requested']} steps, "
        f"feedback share {100 * cl['feedback_share']:.1f} % (above {100 * cl['share_limit']:g} %: "
        f"{'no' if cl['feedback_share'] < cl['share_limit'] else 'yes'}), "
        f"tracking RMS {cl['tracking_rms']:.2e} rad (max {cl['tracking_max']:.2e}), "
        f"stance foot down {100 * cl['stance_contact']:.1f} %, {cl['grazes']} swing-foot grazes{fell}"
    )


def _print_summary(results: list[dict[str, Any]]) -> None:
    print(f"summary  {sum(r['passed'] for r in results)}/{len(results)} passed")
    for r in results:
        idr, cl = r["inverse_dynamics"], r["closed_loop"]
        failed = _failed_names(r)
        loop = (
            f"not replayed ({r['replay_error']})"
            if cl is None
            else f"walked {cl['steps_walked']}/{cl['steps_requested']} steps, tracking RMS "
            f"{cl['tracking_rms']:.1e} rad, feedback share {100 * cl['feedback_share']:.1f} %"
        )
        print(
            f"  {_verdict(r['passed'])}  {r['demo']}: "
            + (f"failed {', '.join(failed)}; " if failed else "")
            + f"inverse dynamics {idr['relative_residual']:.1e}; reported: {loop}"
        )
