"""``ioc-bench human``: the human track. Infer a cost from a person's walking at one treadmill
speed, predict the same person's other speeds, and score the predictions against the
nominal weights and the floor (``docs/human.md``).

One case: ``--subject WBDS01 --train T05 --predict T03,T04,T06 --algorithm bilevel``
(``--train T04,T05`` gives the algorithm both speeds' steps at once, for one cost). A case
list: ``--suite human-smoke`` (or ``human``), which resumes: a case whose result is already
in ``--out`` is not run again. ``--list`` prints the case lists. With ``--out DIR`` each case's
JSON result (``ALGORITHM/CASE.json``) and its figure (``.png`` beside it) are written there,
atomically; without it nothing is written. Every input (the data folder and every file a
case reads, the algorithm and its config, the speeds) is checked before any solve: bad
input exits 2 with one line. Exit code 1 when a case failed (its record says why).
"""

from __future__ import annotations

import argparse
import json
import sys
from dataclasses import replace
from pathlib import Path

from ioc_bench.cli.common import (
    UsageError,
    add_json_flag,
    input_dir,
    json_object,
    output_dir,
    path_arg,
    positive_int,
    print_json,
    seed_int,
    usage_errors,
)

#: Largest result file read back when resuming (a case's record is about 100 kB).
MAX_RESULT_BYTES = 10_000_000


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("human", help="infer a cost from human walking, predict other speeds", description=__doc__)
    p.add_argument("--subject", help="WBDS subject code, e.g. WBDS01")
    train_help = "training speed code, e.g. T05; several, comma-separated, are given to the algorithm at once"
    p.add_argument("--train", help=train_help)
    p.add_argument("--predict", help="predicted speed codes, comma-separated (default: the other shipped speeds)")
    p.add_argument("--algorithm", default="bilevel", help="registered algorithm (default bilevel)")
    p.add_argument("--config", type=json_object, default={}, help="algorithm config overrides as JSON")
    p.add_argument("--seed", type=seed_int, default=0, help="seed of the algorithm and the forward starts (>= 0)")
    p.add_argument("--starts", type=positive_int, default=None, help="starts per forward solve (default 3)")
    floor_help = "extra weight directions solved at every speed for the floor, ';'-separated, or 'none' (default 1,4,0)"
    p.add_argument("--floor", help=floor_help)
    p.add_argument("--suite", help="run a case list instead of one case: human-smoke or human")
    p.add_argument("--list", action="store_true", help="print the case lists and exit")
    p.add_argument("--data", type=path_arg, help="a folder of the WBDS ASCII layout (default: the shipped subset)")
    p.add_argument("--out", type=path_arg, help="folder for the results and figures (default: write nothing)")
    add_json_flag(p)
    p.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    from ioc_bench.human.track import HUMAN_SUITES

    if args.list:
        return _list(HUMAN_SUITES, args.json)
    specs = _specs(args)
    data = _data(args.data)
    steps = _steps(specs, data)
    out = output_dir(args.out) if args.out is not None else None
    results = [_run_one(spec, data, steps, out, args.json) for spec in specs]
    if args.suite is not None:
        _report_suite(args.suite, results, out, args.json)
    elif args.json:
        print_json(results[0])
    return 1 if any(r["status"] == "failed" for r in results) else 0


def _report_suite(name: str, results: list[dict], out: Path | None, as_json: bool) -> None:
    """The run's summary per algorithm: printed, and written to ``--out/summary.json`` and
    ``summary.md`` (a Markdown table for a leaderboard)."""
    from ioc_bench.fileio import atomic_write_json, atomic_write_text
    from ioc_bench.human.track import summarize, summary_markdown

    summary = {"suite": name, "algorithms": summarize(results)}
    if out is not None:
        atomic_write_json(out / "summary.json", summary)
        atomic_write_text(out / "summary.md", f"## {name}\n\n" + summary_markdown(summary["algorithms"]))
    if as_json:
        print_json(summary | {"cases": results})
        return
    print(f"{name}: {len(results)} cases")
    for algorithm, row in summary["algorithms"].items():
        print(
            f"  {algorithm:16s} fit {_f(row['fit_rmse_deg'])} deg  prediction {_f(row['prediction_rmse_deg'])} deg  "
            f"beat nominal {row['beat_nominal']}/{row['predictions']}  median skill {_f(row['median_skill'], 2)} "
            f"(run floor {_f(row['median_skill_run_floor'], 2)})  failed {row['failed']}  {row['time_s']:.0f} s"
        )


def _list(suites: dict, as_json: bool) -> int:
    listing = {name: [spec.identity() | {"key": spec.key} for spec in specs] for name, specs in suites.items()}
    if as_json:
        print_json(listing)
        return 0
    for name, cases in listing.items():
        print(f"{name}: {len(cases)} cases")
        for case in cases:
            print(f"  {case['key']}")
    return 0


def _specs(args: argparse.Namespace) -> list:
    from ioc_bench.human.track import DEFAULT_STARTS, HUMAN_SUITES, SPEED_CODES, HumanCaseSpec
    from ioc_bench.ioc.registry import make_algorithm

    starts = DEFAULT_STARTS if args.starts is None else args.starts
    options = {"seed": args.seed, "starts": starts}
    if args.floor is not None:
        options["floor_weights"] = () if args.floor.strip() == "none" else tuple(args.floor.split(";"))
    if args.suite is not None:
        given = [f"--{k}" for k in ("subject", "train", "predict") if getattr(args, k) is not None]
        given += ["--config"] if args.config else []
        if given:
            raise UsageError(f"--suite runs its own cases: drop {', '.join(given)}")
        if args.suite not in HUMAN_SUITES:
            raise UsageError(f"unknown suite {args.suite!r}: choose from {', '.join(HUMAN_SUITES)}")
        with usage_errors():
            specs = [replace(s, **options) for s in HUMAN_SUITES[args.suite]]
            for spec in {s.algorithm for s in specs}:
                make_algorithm(spec)
        return specs
    if args.subject is None or args.train is None:
        raise UsageError("name a case with --subject and --train (or run --suite NAME, or --list)")
    train = [t.strip() for t in args.train.split(",")]
    predict = args.predict.split(",") if args.predict is not None else [s for s in SPEED_CODES if s not in train]
    with usage_errors():
        codes = tuple(p.strip() for p in predict)
        spec = HumanCaseSpec(
            args.subject, train[0], codes, args.algorithm, config=args.config, also_train=tuple(train[1:]), **options
        )
        make_algorithm(spec.algorithm, **spec.config)  # the name and every config field
    return [spec]


def _data(folder: Path | None):
    from ioc_bench.human.wbds import WbdsData

    if folder is not None:
        input_dir(folder, "--data folder")
    with usage_errors("--data: " if folder is not None else ""):
        return WbdsData(folder)


def _steps(specs: list, data) -> dict:
    """Every step of every case, read and checked before any solve."""
    from ioc_bench.human.step import human_step

    steps = {}
    with usage_errors():
        for spec in specs:
            for code in spec.speeds:
                if (spec.subject, code) not in steps:
                    steps[spec.subject, code] = human_step(data.trial(spec.subject, code))
    return steps


def _run_one(spec, data, steps: dict, out: Path | None, quiet: bool) -> dict:
    from ioc_bench.fileio import atomic_write_json
    from ioc_bench.human.figures import plot_human_case
    from ioc_bench.human.track import run_human_case

    path = None if out is None else out / f"{spec.key}.json"
    done = _finished(path, spec)
    if done is not None:
        if not quiet:
            print(f"{spec.key}: already in {path}, not run again", file=sys.stderr)
        return done
    if not quiet:
        print(f"running {spec.key}", file=sys.stderr)
    record = run_human_case(spec, data).to_dict()
    if path is not None:
        atomic_write_json(path, record)
        humans = {code: steps[spec.subject, code].angles for code in spec.speeds}
        plot_human_case(record, humans, path.with_suffix(".png"))
    if not quiet:
        _print(record)
    return _without_angles(record)


def _finished(path: Path | None, spec) -> dict | None:
    """A result already written for this very case (same identity), else None."""
    if path is None or not path.is_file():
        return None
    from ioc_bench.checks import load_json
    from ioc_bench.fileio import read_bytes

    try:
        record = load_json(read_bytes(path, MAX_RESULT_BYTES, "result file"))
    except (OSError, ValueError):
        return None
    if not isinstance(record, dict) or any(record.get(k) != v for k, v in spec.identity().items()):
        return None
    return _without_angles(record)


def _without_angles(record: dict) -> dict:
    record = json.loads(json.dumps(record))
    scores = [record.get("fit") or {}, *(record.get("also_fit") or {}).values()]
    for score in [*scores, *(record.get("predictions") or {}).values()]:
        score.pop("angles", None)
    return record


def _print(record: dict) -> None:
    w = ", ".join(f"{x:.3f}" if x is not None else "nan" for x in record["weights"])
    reason = f" ({record['reason']})" if record["reason"] else ""
    train = "+".join([record["train"], *record.get("also_train", [])])
    print(f"{record['algorithm']} on {record['subject']} {train}: {record['status']}{reason}")
    print(
        f"  weights ({', '.join(record['features'])}) = [{w}]  "
        f"in {record['wall_time']:.1f} s, {record['n_solves']} solves"
    )
    rows = [("fit", record["train"], record.get("fit"))]
    rows += [("fit", c, s) for c, s in (record.get("also_fit") or {}).items()]
    rows += [("predict", c, s) for c, s in (record.get("predictions") or {}).items()]
    for role, code, score in rows:
        if not score:
            continue
        method = score.get("fit_rmse_deg", score.get("prediction_rmse_deg"))
        print(
            f"  {role:7s} {code}: {_f(method)} deg  nominal {_f(score['nominal_rmse_deg'])}  "
            f"floor {_f(score['floor_rmse_deg'])} ({score['floor_weights']})  skill {_f(score['skill'], 2)}"
            + ("" if score["status"] == "Solve_Succeeded" else f"  (forward solve: {score['status']})")
        )


def _f(value, digits: int = 1) -> str:
    return "n/a" if value is None else f"{value:.{digits}f}"
