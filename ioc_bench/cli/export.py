"""``ioc-bench export``: demonstrations in the formats other tools read (docs/exports.md).

``DEMO`` is a demonstration file or a folder of them (every ``*.npz`` directly in it but
the ``*_qpos.npz`` this command writes). Formats:

- ``sto``: one full stride (the step and its mirror image) as an OpenSim storage file
  with the coordinate names of OpenSim's planar gait models (``pelvis_tilt``,
  ``pelvis_tx``, ``pelvis_ty``, ``hip_flexion_r``, ``knee_angle_r``, ``hip_flexion_l``,
  ``knee_angle_l``), SI units, ``--rate`` rows per second; ``--degrees`` for angles in
  degrees. Default output: ``DEMO`` with the suffix ``.sto``.
- ``qpos``: the same stride as LocoMuJoCo-style arrays (``qpos``, ``qvel``,
  ``joint_names``, ``frequency``) in the MuJoCo model's joints, SI units. Default output:
  ``<DEMO's stem>_qpos.npz`` beside it.
- ``minari``: a Minari dataset of the tracking policy's rollout in
  ``IOCBench/PlanarWalker-v2``, each step's cost-feature increments in its ``infos``, id
  ``ioc-bench/<DEMO's stem>-v0``, under ``--out`` (default Minari's folder:
  ``$MINARI_DATASETS_PATH``, else ``~/.minari/datasets``). Needs the ``export`` extra.

For a folder, ``--out`` is a folder (default: the demonstrations' own); each export is
named as above. Every file is read and every output checked before anything is written;
files are written atomically, and a Minari dataset that exists already is refused. Bad
input exits with code 2 and one line. ``ioc_bench`` does not import ``envs`` (nor MuJoCo)
until this command runs.
"""

from __future__ import annotations

import argparse
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from ioc_bench.cli.common import (
    UsageError,
    add_json_flag,
    input_dir,
    mujoco_log_to_stderr,
    output_dir,
    output_file,
    path_arg,
    positive_float,
    print_json,
    usage_errors,
)

#: The formats, in the order ``--format`` lists them.
FORMATS = ("sto", "qpos", "minari")
#: What a qpos export's name ends with (such files in a folder are not read as demonstrations).
QPOS_SUFFIX = "_qpos.npz"


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("export", help="write demonstrations as an OpenSim .sto, qpos/qvel arrays or a Minari dataset")
    p.description = __doc__
    p.add_argument("demo", type=path_arg, metavar="DEMO", help="a demonstration file (.npz) or a folder of them")
    p.add_argument("--format", choices=FORMATS, required=True, help="sto, qpos or minari")
    p.add_argument(
        "--out",
        type=path_arg,
        default=None,
        help="the file to write (sto, qpos; a folder for a folder of demonstrations) or Minari's datasets folder",
    )
    p.add_argument("--rate", type=_rate, default=None, help="samples per second (sto, qpos; default 100)")
    p.add_argument(
        "--leg-length",
        type=positive_float,
        default=None,
        metavar="METRES",
        help="the walker's leg in metres (sto, qpos; default 1, the paper's units)",
    )
    p.add_argument("--degrees", action="store_true", help="angles in degrees, inDegrees=yes (sto)")
    add_json_flag(p)
    p.set_defaults(run=run)


def _rate(text: str) -> float:
    """An argparse type: samples per second, positive and at most ``MAX_RATE``."""
    from envs.export.joints import MAX_RATE  # lazily: only this command's parse needs it

    value = positive_float(text)
    if value > MAX_RATE:
        raise argparse.ArgumentTypeError(f"must be at most {MAX_RATE:g} samples per second, got {text!r}")
    return value


@dataclass(frozen=True)
class _Job:
    """One demonstration to export and where to."""

    source: Path
    demo: Any
    target: Path | str  # a file (sto, qpos) or a dataset id (minari)


def run(args: argparse.Namespace) -> int:
    _check_options(args)
    sources = _sources(args.demo)
    from ioc_bench.demo import Demonstration

    demos = []
    for path in sources:
        with usage_errors():
            demos.append((path, Demonstration.load(path)))  # every problem with a file is a DemonstrationFileError
    from envs.checks import check_replayable  # lazily: ioc_bench must not need envs (or MuJoCo) to import

    for path, demo in demos:  # every demonstration checked before the first export
        with usage_errors(f"{path}: "):
            check_replayable(demo)
    jobs = _minari_jobs(args, demos) if args.format == "minari" else _file_jobs(args, demos)
    for job in jobs:  # each reported as soon as it is written
        result = _export(job, args)
        if args.json:
            print_json(result)
        else:
            _print_result(result)
    return 0


def _check_options(args: argparse.Namespace) -> None:
    """Options that do not apply to the format are refused, not ignored."""
    given = {"--rate": args.rate is not None, "--leg-length": args.leg_length is not None, "--degrees": args.degrees}
    applies = {"sto": set(given), "qpos": {"--rate", "--leg-length"}, "minari": set()}[args.format]
    wrong = [name for name, on in given.items() if on and name not in applies]
    if wrong:
        raise UsageError(f"{wrong[0]} does not apply to --format {args.format}")


def _sources(path: Path) -> list[Path]:
    """The demonstration files to read: ``path``, or the ``*.npz`` directly in the folder ``path``."""
    if not path.is_dir():
        return [path]
    folder = input_dir(path, "demonstration folder")
    files = sorted(p for p in folder.glob("*.npz") if not p.name.endswith(QPOS_SUFFIX))
    if not files:
        raise UsageError(f"{folder} holds no demonstration files (*.npz)")
    return files


def _file_jobs(args: argparse.Namespace, demos: list[tuple[Path, Any]]) -> list[_Job]:
    """Where each sto or qpos export goes, every output checked before the work."""
    name = (lambda p: p.with_suffix(".sto").name) if args.format == "sto" else (lambda p: p.stem + QPOS_SUFFIX)
    if args.demo.is_dir():
        folder = output_dir(args.out) if args.out is not None else args.demo
        targets = [folder / name(path) for path, _ in demos]
    else:
        targets = [args.out if args.out is not None else demos[0][0].parent / name(demos[0][0])]
    for (path, _), target in zip(demos, targets):
        output_file(target, "--out" if args.out is not None else "export output")
        if target.exists() and target.samefile(path):
            raise UsageError(f"--out {target} is the demonstration itself: the export would replace it")
    return [_Job(path, demo, target) for (path, demo), target in zip(demos, targets)]


def _minari_jobs(args: argparse.Namespace, demos: list[tuple[Path, Any]]) -> list[_Job]:
    """The datasets to make, checked before the work: Minari installed, the folder writable, every id free."""
    from envs.export.rollouts import MissingExtraError, check_dataset_free, dataset_id, default_root, import_minari
    from envs.tracking import TrackingPolicy

    try:
        import_minari()
    except MissingExtraError as exc:
        raise UsageError(str(exc)) from None
    root = output_dir(args.out) if args.out is not None else output_dir(default_root(), "Minari's datasets folder")
    ids = [dataset_id(path.stem) for path, _ in demos]
    for (path, _), other in zip(demos, ids):
        if ids.count(other) > 1:
            raise UsageError(f"{path}: another demonstration of the folder also makes the Minari dataset {other}")
    for (path, demo), name in zip(demos, ids):
        with usage_errors(f"{path}: "):
            check_dataset_free(root, name)
            TrackingPolicy(demo)  # a demonstration the policy cannot phase is refused before any rollout
    args.out = root.absolute()
    return [_Job(path, demo, name) for (path, demo), name in zip(demos, ids)]


def _export(job: _Job, args: argparse.Namespace) -> dict[str, Any]:
    from envs.export.joints import DEFAULT_LEG_LENGTH, DEFAULT_RATE

    report: dict[str, Any] = {"demo": str(job.source), "format": args.format}
    if args.format == "minari":
        from envs.export.rollouts import write_minari

        mujoco_log_to_stderr()  # never a MUJOCO_LOG.TXT in the current folder
        folder, data = write_minari(job.demo, args.out, str(job.target), job.source)
        return report | {
            "out": str(folder),
            "dataset_id": str(job.target),
            "datasets_path": str(args.out),
            "episodes": 1,
            "steps": len(data),
            "heel_strikes": int(data.infos["heel_strikes"][-1]),
            "ended": "fell" if data.terminations[-1] else "time limit",
        }
    rate = DEFAULT_RATE if args.rate is None else args.rate
    leg = DEFAULT_LEG_LENGTH if args.leg_length is None else args.leg_length
    with usage_errors(f"{job.source}: "):
        if args.format == "sto":
            from envs.export.opensim import write_sto

            path, series = write_sto(job.demo, job.target, rate, leg, args.degrees)
        else:
            from envs.export.joints import write_qpos

            path, series = write_qpos(job.demo, job.target, rate, leg, job.source)
    return report | {
        "out": str(path),
        "rows": len(series.times),
        "rate": series.rate,
        "stride_time": series.stride_time,
        "step_length": series.step_length,
        "leg_length": series.units.leg_length,
        "angles": "deg" if args.format == "sto" and args.degrees else "rad",
    }


def _print_result(r: dict[str, Any]) -> None:
    if r["format"] == "minari":
        print(
            f"wrote    {r['out']}: Minari dataset {r['dataset_id']}, 1 episode of {r['steps']} steps "
            f"({r['heel_strikes']} heel strikes, ended by {r['ended']}) from {r['demo']}"
        )
        print(f"load     MINARI_DATASETS_PATH={r['datasets_path']}, then minari.load_dataset({r['dataset_id']!r})")
        return
    what = "OpenSim coordinates" if r["format"] == "sto" else "qpos/qvel arrays"
    print(
        f"wrote    {r['out']}: {what} of one stride (two steps) from {r['demo']}: {r['rows']} rows at "
        f"{r['rate']:g} Hz over {r['stride_time']:.3f} s, step {r['step_length']:.3f} m, "
        f"leg {r['leg_length']:g} m, angles in {r['angles']}"
    )
