"""``ioc-bench run``: run a benchmark suite (default: smoke, log-barrier) and print its leaderboard.

Finished cases are written one file each, at once and atomically; running the same
command again resumes, skipping finished cases. Failed cases (the algorithm failed, the
case timed out, its worker died) are recorded and shown, and retried by the next run
unless ``--keep-failed`` is given. Everything (suite, algorithm, config, output folder,
result files already there, the Ray cluster) is checked before any work.
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
    input_dir,
    json_object,
    output_dir,
    path_arg,
    positive_float,
    positive_int,
    print_json,
    usage_errors,
)
from ioc_bench.runner.executor import DEFAULT_TIME_LIMIT, EXECUTORS


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("run", help="run a benchmark suite and print its leaderboard", description=__doc__)
    p.add_argument("--suite", default=None, help="suite name (default smoke; see --list)")
    p.add_argument("--algorithm", default="log-barrier", help="registered algorithm (default log-barrier)")
    p.add_argument("--config", type=json_object, default={}, help="algorithm config overrides as JSON")
    p.add_argument("--out", type=path_arg, default=Path("results"), help="results directory (default results/)")
    p.add_argument("--workers", type=positive_int, default=None, help="parallel cases (default: all cores)")
    p.add_argument("--executor", choices=tuple(EXECUTORS), default="local", help="local processes or a Ray cluster")
    p.add_argument("--address", default=None, help="Ray cluster address, e.g. 127.0.0.1:6379 (default: a local Ray)")
    time_help = f"seconds per case (default {DEFAULT_TIME_LIMIT:g})"
    p.add_argument("--time-limit", type=positive_float, default=DEFAULT_TIME_LIMIT, help=time_help)
    p.add_argument("--keep-failed", action="store_true", help="do not retry cases whose stored result is a failure")
    p.add_argument("--list", action="store_true", help="list the suites (or the one --suite names) and exit")
    p.add_argument("--data", type=path_arg, default=None, help="a WBDS folder for a human suite (default: shipped)")
    add_model_arg(p, default=None)
    add_json_flag(p)
    p.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    from ioc_bench.cli.common import progress_bar
    from ioc_bench.human.suites import HumanSuite
    from ioc_bench.runner.leaderboard import markdown, summary
    from ioc_bench.runner.results import read_result
    from ioc_bench.runner.run import plan_run
    from ioc_bench.runner.tracks import get_suite, suites

    if args.list:
        with usage_errors():
            listed = [get_suite(args.suite)] if args.suite is not None else list(suites().values())
        return _list_suites(listed, args.json)
    args.suite = args.suite or "smoke"
    with usage_errors():
        suite = get_suite(args.suite)
    is_human = isinstance(suite, HumanSuite)  # its cases read a WBDS folder (--data)
    if args.data is not None and not is_human:
        raise UsageError(f"--data names a WBDS folder for the human suites; {args.suite} is a synthetic suite")
    with usage_errors():
        if is_human:
            data = None if args.data is None else str(input_dir(args.data, "--data folder"))
            specs = suite.cases(args.algorithm, args.config, model=args.model, data=data)
            _check_human_data(specs)
        else:
            specs = suite.cases(args.algorithm, args.config, model=args.model)
    output_dir(args.out)
    check_cache()
    with usage_errors():
        plan = plan_run(
            specs, args.out, args.workers, args.time_limit, args.executor, args.address, keep_failed=args.keep_failed
        )
    say = (lambda msg: print(msg, file=sys.stderr)) if not args.json else (lambda msg: None)
    say(f"suite {args.suite}: {len(specs)} cases of {args.algorithm} -> {args.out}/")
    failures = [0]
    with progress_bar(len(specs), "cases", enabled=not args.json) as bar:

        def on_case(spec, result) -> None:
            failures[0] += result.failed
            bar.update(1)
            bar.set_postfix(failures=failures[0])
            if not args.json:
                bar.write(f"  {spec.key}: {result.headline()}, {result.wall_time:.0f} s", file=sys.stderr)

        try:
            run_summary = plan.run(on_case, say)
        except KeyboardInterrupt:
            print(
                f"\ninterrupted; finished cases are in {args.out}/ - rerun the same command to resume", file=sys.stderr
            )
            return 130
    with usage_errors():
        stored = [(s.key, read_result(s.path(args.out), args.out)) for s in specs if s.path(args.out).is_file()]
    results = [r for _, r in stored]
    if args.json:
        print_json({"summary": run_summary.__dict__} | summary(results))
    else:
        retried = f" ({run_summary.retried} of them retried)" if run_summary.retried else ""
        say(
            f"{run_summary.ran} run{retried}, {run_summary.skipped} already done, {run_summary.failed} failed, "
            f"{run_summary.wall_time:.0f} s"
        )
        failed = [(key, r) for key, r in stored if r.failed]
        if failed:
            hint = "" if not args.keep_failed else "; rerun without --keep-failed to retry them"
            say(f"{len(failed)} case(s) failed{hint}:")
            for key, r in failed:
                say(f"  {key}: {' '.join(r.reason.split())}")
        print(markdown(results, str(args.out)))
    return 0


def _check_human_data(specs: list) -> None:
    """Read and check every WBDS file the cases need, before any solve (``WbdsDataError``, one line)."""
    for spec in specs:
        spec.steps()
        spec.training_steps()


def _list_suites(suites: list, as_json: bool) -> int:
    rows = [
        {
            "name": suite.name,
            "cases": len(suite),
            "model": suite.model,
            "description": suite.description,
        }
        for suite in suites
    ]
    if as_json:
        print_json({"suites": rows})
    else:
        for row in rows:
            print(f"{row['name']:<14} {row['cases']:3d} cases  {row['model']:<8} {row['description']}")
    return 0
