"""``ioc-bench human``: one case of the human track. Infer a cost from a person's walking at
one treadmill speed (or several), predict the same person's other speeds, and score the
predictions against the nominal weights, the floor and copying the person (``docs/human.md``).

``--subject WBDS01 --train T05 --predict T03,T04,T06 --algorithm bilevel`` (``--train
T04,T05`` gives the algorithm both speeds' steps at once, for one cost; ``--population
WBDS02,WBDS03`` fits the cost on those subjects' steps instead and predicts this subject's;
``--model rolling-feet`` maps the person's steps to the walker with rolling feet and a free
knee on the subject's body instead of the paper's walker; ``--basis energetics`` weighs
positive joint work and the heel-strike collision loss beside the efforts).
With ``--out DIR`` the case runs as any suite's case does (``ioc-bench run``): its result
``ALGORITHM/CASE.json`` is written atomically under a lock, resumed if already there, and its
figure written beside it; without it nothing is written. A whole suite: ``ioc-bench run
--suite human --algorithm A``. Every input (the data folder and every file the case reads,
the algorithm and its config, the speeds) is checked before any solve: bad input exits 2
with one line. Exit code 1 when the case failed (its record says why).
"""

from __future__ import annotations

import argparse
import sys

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
from ioc_bench.model.catalogue import DEFAULT_MODEL


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("human", help="infer a cost from human walking, predict other speeds", description=__doc__)
    p.add_argument("--subject", help="WBDS subject code, e.g. WBDS01")
    train_help = "training speed code, e.g. T05; several, comma-separated, are given to the algorithm at once"
    p.add_argument("--train", help=train_help)
    p.add_argument("--predict", help="predicted speed codes, comma-separated (default: the other shipped speeds)")
    p.add_argument("--population", help="fit on these other subjects' steps instead, comma-separated")
    p.add_argument("--algorithm", default="bilevel", help="registered algorithm (default bilevel)")
    p.add_argument("--config", type=json_object, default={}, help="algorithm config overrides as JSON")
    p.add_argument("--seed", type=seed_int, default=0, help="seed of the algorithm and the forward starts (>= 0)")
    p.add_argument("--starts", type=positive_int, default=None, help="starts per forward solve (default 3)")
    floor_help = "extra weight directions solved at every speed for the floor, ';'-separated, or 'none' (default 1,4,0)"
    p.add_argument("--floor", help=floor_help)
    model_help = (
        f"gait model the person's steps are mapped to (default {DEFAULT_MODEL}; rolling-feet: rolling feet, free knee)"
    )
    p.add_argument("--model", default=DEFAULT_MODEL, help=model_help)  # checked by the case: one line, exit 2
    task_help = "what the walker is told: speed (step length free; default) or speed-and-step (the person's too)"
    p.add_argument("--task", default="speed", help=task_help)  # checked by the case
    basis_help = (
        "cost basis weighed: effort (default: hip, knee, dtau), effort-work (+ work), energetics (+ work, collision)"
    )
    p.add_argument("--basis", default="effort", help=basis_help)  # checked by the case
    p.add_argument("--suite", help=argparse.SUPPRESS)
    p.add_argument("--data", type=path_arg, help="a folder of the WBDS ASCII layout (default: the shipped subset)")
    p.add_argument("--out", type=path_arg, help="results folder for the case and its figure (default: write nothing)")
    add_json_flag(p)
    p.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    from ioc_bench.runner.run import run_one

    if args.suite is not None:
        raise UsageError(f"a suite runs with: ioc-bench run --suite {args.suite} --algorithm {args.algorithm}")
    spec = _spec(args)
    out = output_dir(args.out) if args.out is not None else None
    say = (lambda msg: None) if args.json else (lambda msg: print(msg, file=sys.stderr))
    record = run_one(spec, out, say)
    if args.json:
        print_json(record.to_dict())
    else:
        _print(record)
    return 1 if record.failed else 0


def _spec(args: argparse.Namespace):
    from ioc_bench.human.case import DEFAULT_STARTS, HumanCaseSpec
    from ioc_bench.human.suites import SPEED_CODES
    from ioc_bench.ioc.registry import make_algorithm

    if args.subject is None or args.train is None:
        raise UsageError("name a case with --subject and --train (a suite runs with ioc-bench run --suite NAME)")
    data = None if args.data is None else str(input_dir(args.data, "--data folder"))
    train = [t.strip() for t in args.train.split(",")]
    population = tuple(p.strip() for p in args.population.split(",")) if args.population else ()
    default = list(SPEED_CODES) if population else [s for s in SPEED_CODES if s not in train]
    predict = [p.strip() for p in args.predict.split(",")] if args.predict is not None else default
    options = {"seed": args.seed, "starts": DEFAULT_STARTS if args.starts is None else args.starts}
    if args.floor is not None:
        options["floor_weights"] = () if args.floor.strip() == "none" else tuple(args.floor.split(";"))
    with usage_errors():
        spec = HumanCaseSpec(
            args.subject, train[0], tuple(predict), args.algorithm, config=args.config, also_train=tuple(train[1:]),
            population=population, model=args.model, task=args.task, basis=args.basis, data=data, **options,
        )  # fmt: skip
        make_algorithm(spec.algorithm, **spec.config)  # the name and every config field
        spec.steps()  # every file the case reads, checked before any solve
        spec.training_steps()
    return spec


def _print(record) -> None:
    from ioc_bench.bases import DEFAULT_BASIS

    w = ", ".join(f"{x:.3f}" for x in record.weights)
    reason = f" ({record.reason})" if record.reason else ""
    train = "+".join([record.train, *record.also_train])
    source = f" fitted on {'+'.join(record.population)}" if record.population else ""
    qualifiers = [q for q, plain in ((record.model, DEFAULT_MODEL), (record.basis, DEFAULT_BASIS)) if q != plain]
    model = f" ({', '.join(qualifiers)})" if qualifiers else ""
    print(f"{record.algorithm} on {record.subject} {train}{source}{model}, task {record.task}: {record.status}{reason}")
    print(f"  weights ({', '.join(record.features)}) = [{w}]  in {record.wall_time:.1f} s, {record.n_solves} solves")
    for code, s in sorted(record.scores.items(), key=lambda item: (item[1].role != "fit", item[0])):
        copy = f"  copy {_f(s.copy_rmse_deg)} ({s.copy_from})  adaptation {_f(s.adaptation_deg)} (copy's "
        copy = copy + f"{_f(s.copy_adaptation_deg)})" if s.copy_from else ""
        status = "" if s.status == "Solve_Succeeded" else f"  (forward solve: {s.status})"
        print(
            f"  {s.role:10s} {code}: {_f(s.rmse_deg)} deg  nominal {_f(s.nominal_rmse_deg)}  "
            f"floor {_f(s.floor_rmse_deg)} ({s.floor_weights})  skill {_f(s.skill, 2)}{copy}{status}"
        )
        print(f"             step length {_f(s.step_length_walker, 3)} L (person {_f(s.step_length, 3)}){_change(s)}")


def _change(s) -> str:
    """The change a prediction carried from another speed predicts, against the baselines'."""
    if not s.continued_from:
        return ""
    family = ", changed family" if s.family_changed else ""
    pop = s.population_adaptation_deg
    population = f", population {_f(pop)}" if pop == pop else ""  # NaN: no population baseline
    return (
        f"\n             from {s.continued_from}: change R^2 {_f(s.change_r2, 2)}, change error "
        f"{_f(s.adaptation_deg)} deg (copy {_f(s.copy_adaptation_deg)}{population}){family}; "
        f"the cheapest cold start here {_f(s.cold_rmse_deg)} deg"
    )


def _f(value, digits: int = 1) -> str:
    return "n/a" if value is None or value != value else f"{value:.{digits}f}"
