"""How close can a walker with feet come to a person's step? (docs/feet.md)

For every shipped WBDS trial and every candidate model (the paper's walker; its knee-lock
optional; rolling feet; feet on actuated ankles), on the subject's own body (Winter's
table through :mod:`ioc_bench.human`) at the trial's task (speed and step length):

- ``projection``: the model's step closest to the person's segment angles with the model's
  dynamics, contact and limits holding (tracking the angles, a vanishing effort): the floor
  over *every* cost, a lower bound of any weight direction's fit;
- ``floor``: the best fit of the optimal steps of :data:`DIRECTIONS` weight directions
  (each solved from the projection, and from the rough guess where that start fails):
  the floor the human track measures, over these directions;
- the RMSE is in degrees over the four leg segments and, for a model with feet on
  ankles, also over the leg segments and both feet (``rmse_feet``).

And ``--timing``: the cold solve of every model at the synthetic default (speed 0.27,
nominal weights, perturbed rough guesses as ``ioc-bench speed`` draws them), median of 7.

    python studies/feet_floor.py --out docs/data/feet_floor.jsonl            # ~40 min on 1 core
    python studies/feet_floor.py --out docs/data/feet_floor.jsonl --timing   # ~5 min
    python studies/feet_floor.py --out docs/data/feet_floor.jsonl --table
"""

from __future__ import annotations

import argparse
import json
import statistics
import time
from pathlib import Path

import numpy as np

from ioc_bench.features import cost_features
from ioc_bench.human import WbdsData, human_step
from ioc_bench.human.step import CONTRALATERAL_PHASE, HumanStep
from ioc_bench.model.feet import FootedParams, footed_model, footed_params, from_walker
from ioc_bench.model.gait_model import GaitModel, GuessShape
from ioc_bench.model.linkage import place
from ioc_bench.model.params import WalkerParams
from ioc_bench.model.walker import WALKER
from ioc_bench.task import Task
from ioc_bench.trajopt.forward_problem import SolveRequest, get_forward_problem
from ioc_bench.trajopt.initial_guess import perturbed_step, rough_step
from ioc_bench.trajopt.solution import StartPoint
from ioc_bench.trajopt.tracking import Tracking

#: Candidate models: (label, feet, knee).
CANDIDATES = (
    ("walker", "point", "lock"),
    ("free-knee", "point", "free"),
    ("roll", "roll", "free"),
    ("ankle", "ankle", "free"),
)
#: Weight directions over (hip, knee, [ankle,] dtau): nominal, each alone, pairs.
DIRECTIONS = {
    3: ((1, 1, 1), (1, 0.05, 0.05), (0.05, 1, 0.05), (0.05, 0.05, 1), (1, 1, 0.05), (1, 0.05, 1), (0.05, 1, 1)),
    4: (
        (1, 1, 1, 1),
        (1, 0.05, 0.05, 0.05),
        (0.05, 1, 0.05, 0.05),
        (0.05, 0.05, 1, 0.05),
        (0.05, 0.05, 0.05, 1),
        (1, 1, 0.05, 1),
        (1, 1, 1, 0.05),
    ),
}
#: Tracking strength of the projection and the effort weight left in it (a vanishing cost).
TRACK_STRENGTH, PROJECTION_EFFORT = 10.0, 1e-4
LEG_SEGMENTS = ("thigh_stance", "shank_stance", "thigh_swing", "shank_swing")
FEET = ("foot_stance", "foot_swing")


def foot_angles(step: HumanStep, trial) -> np.ndarray:
    """(T, 2) stance and swing foot angles of the step, walker convention (minus WBDS's
    FootAngleZ, toe up positive, 0 with the sole level), both sides averaged as the legs are."""
    from scipy.interpolate import CubicSpline

    y = -np.radians(0.5 * (trial.angles["RFootAngleZ"] + trial.angles["LFootAngleZ"]))
    y[0] = y[-1] = 0.5 * (y[0] + y[-1])
    spline = CubicSpline(np.linspace(0, 1, len(y)), y, bc_type="periodic")
    s = step.fractions
    return np.column_stack(
        [spline(CONTRALATERAL_PHASE * s), spline((1 - CONTRALATERAL_PHASE + CONTRALATERAL_PHASE * s) % 1)]
    )


def candidate(label: str, feet: str, knee: str, step: HumanStep | None) -> tuple[GaitModel, object]:
    """The candidate's model and the subject's parameters (default body without a step)."""
    if label == "walker":
        return WALKER, step.params if step else WalkerParams()
    if feet == "ankle":
        if step is None:
            params = FootedParams(feet=feet, knee=knee)
        else:
            b = step.body.lengths
            params = footed_params(b.thigh, b.shank, b.ankle_height, b.foot, step.body.height, feet, knee)
    else:
        params = from_walker(step.params if step else WalkerParams(), feet, knee)
    return footed_model(f"study-{label}", params), params


def target_angles(model: GaitModel, step: HumanStep, feet: np.ndarray) -> dict[str, np.ndarray]:
    """Segment -> (T,) the person's angle of every segment the model has and a lab measures."""
    names = [s.name for s in model.linkage(model.default_params).segments]
    out = {n: step.angles[:, j] for j, n in enumerate(LEG_SEGMENTS)}
    if "foot_stance" in names:
        out |= {n: feet[:, j] for j, n in enumerate(FEET)}
    return out


def human_start(forward, model, params, step: HumanStep, targets) -> np.ndarray:
    """A start point placed from the person's angles (torso at the guess's lean)."""
    link = model.linkage(params)
    names = [s.name for s in link.segments]
    theta = np.zeros((step.n_knots, len(names)))
    theta[:, names.index("torso")] = GuessShape().lean
    for n, a in targets.items():
        theta[:, names.index(n)] = a
    q = np.array([place(link, row) for row in theta])
    v = np.gradient(q, step.dt, axis=0)
    force = np.zeros(forward.step.layout.blocks["force"][1])
    force[:, forward.step.contact, 1] = params.total_mass * params.gravity
    return forward.step.layout.pack({"dt": step.dt, "q": q, "v": v, "force": force})


def tracking(forward, targets: dict[str, np.ndarray]) -> Tracking:
    """Track the targets' angles, each normalised by its span, the mean over them."""
    names = forward.step.seg_names
    t = forward.n_knots
    ref, weight = np.zeros((t, forward.step.n_track)), np.zeros((t, forward.step.n_track))
    for n, a in targets.items():
        col = 3 * names.index(n) + 2
        ref[:, col] = a
        weight[:, col] = TRACK_STRENGTH / (np.ptp(a) ** 2 * len(targets) * t)
    return Tracking(ref, weight)


def rmse(result, forward, targets: dict[str, np.ndarray], segments) -> float:
    names = forward.step.seg_names
    diff = [result.trajectory.q[:, names.index(n), 2] - targets[n] for n in segments if n in targets]
    return float(np.degrees(np.sqrt(np.mean(np.square(diff)))))


def weights_for(forward, model, direction) -> np.ndarray:
    cost = cost_features(model)
    w = np.array([dict(zip(cost, direction)).get(f, 0.0) for f in forward.features], dtype=float)
    return w / np.linalg.norm(w)


def measure_trial(label, feet, knee, step: HumanStep, trial) -> dict:
    """Projection and weight-direction floors of one candidate on one trial."""
    model, params = candidate(label, feet, knee, step)
    forward = get_forward_problem(model)
    targets = target_angles(model, step, foot_angles(step, trial))
    all_segments = LEG_SEGMENTS + FEET
    nominal = weights_for(forward, model, (1,) * len(cost_features(model)))
    proj = forward.solve(
        SolveRequest(
            StartPoint(human_start(forward, model, params, step, targets)),
            params,
            step.task,
            nominal * PROJECTION_EFFORT,
            tracking(forward, targets),
        )
    )
    guess = forward.step.layout.pack(
        rough_step(model, params, step.task.speed, forward.n_knots, GuessShape(step=step.task.step_length))
    )
    out = {
        "model": label,
        "subject": step.subject,
        "speed": step.speed_code,
        "projection_ok": proj.report.success,
        "projection": rmse(proj, forward, targets, LEG_SEGMENTS),
        "projection_feet": rmse(proj, forward, targets, all_segments),
        "directions": [],
    }
    for direction in DIRECTIONS[len(cost_features(model))]:
        w = weights_for(forward, model, direction)
        sols = [forward.solve(SolveRequest(StartPoint(proj.x), params, step.task, w))]
        if not sols[0].report.success:  # the rough guess only when the projection's start fails
            sols.append(forward.solve(SolveRequest(StartPoint(guess), params, step.task, w)))
        ok = [r for r in sols if r.report.success]
        best = min(ok, key=lambda r: r.report.objective) if ok else None
        out["directions"].append(
            {
                "weights": list(direction),
                "ok": best is not None,
                "rmse": rmse(best, forward, targets, LEG_SEGMENTS) if best else None,
                "rmse_feet": rmse(best, forward, targets, all_segments) if best else None,
                "time": sum(r.report.wall_time for r in sols),
            }
        )
    fits = [d["rmse"] for d in out["directions"] if d["ok"]]
    out["floor"] = min(fits) if fits else None
    fits_feet = [d["rmse_feet"] for d in out["directions"] if d["ok"]]
    out["floor_feet"] = min(fits_feet) if fits_feet else None
    return out


def timing(labels, repeats: int = 7) -> list[dict]:
    """Median cold solve of each candidate at the synthetic default (see the module docstring)."""
    rows = []
    for label, feet, knee in CANDIDATES:
        if label not in labels:
            continue
        model, params = candidate(label, feet, knee, None)
        t0 = time.perf_counter()
        forward = get_forward_problem(model)
        build = time.perf_counter() - t0
        w, task = weights_for(forward, model, (1,) * len(cost_features(model))), Task(0.27)
        results = []
        for i in range(repeats):
            x0 = forward.step.layout.pack(
                perturbed_step(model, params, task.speed, forward.n_knots, np.random.default_rng([1, i]))
            )
            results.append(forward.solve(SolveRequest(StartPoint(x0), params, task, w)))
        rows.append(
            {
                "model": label,
                "timing": True,
                "build_s": build,
                "n_x": forward.n_x,
                "n_g": forward.n_g,
                "cold_median_s": statistics.median(r.report.wall_time for r in results),
                "cold_median_iterations": statistics.median(r.report.iterations for r in results),
                "failures": sum(not r.report.success for r in results),
            }
        )
        print(json.dumps(rows[-1]), flush=True)
    return rows


def table(path: Path) -> str:
    rows = [json.loads(line) for line in path.read_text().splitlines() if line.strip()]
    lines = [
        "| model | trials | projection median (range) | floor median (range) | floor with feet median |",
        "|---|---|---|---|---|",
    ]
    for label, *_ in CANDIDATES:
        mine = [r for r in rows if r["model"] == label and not r.get("timing")]
        if not mine:
            continue
        cell = lambda v: f"{statistics.median(v):.2f} ({min(v):.2f}-{max(v):.2f})" if v else "-"  # noqa: E731
        proj = [r["projection"] for r in mine]
        floor = [r["floor"] for r in mine if r["floor"] is not None]
        feet = [r["floor_feet"] for r in mine if r["floor_feet"] is not None]
        lines.append(
            f"| {label} | {len(mine)} | {cell(proj)} | {cell(floor)} | {cell(feet) if label == 'ankle' else '-'} |"
        )
    lines += [
        "",
        "| model | n_x | n_g | build (s) | cold median (s) | iterations | failures |",
        "|---|---|---|---|---|---|---|",
    ]
    for r in (r for r in rows if r.get("timing")):
        lines.append(
            f"| {r['model']} | {r['n_x']} | {r['n_g']} | {r['build_s']:.1f} | {r['cold_median_s']:.2f} | "
            f"{r['cold_median_iterations']:.0f} | {r['failures']} |"
        )
    return "\n".join(lines)


def _measure(trial, labels, out) -> None:
    """Every chosen candidate on one trial, a JSON line each."""
    step = human_step(trial)
    for label, feet, knee in CANDIDATES:
        if label in labels:
            row = measure_trial(label, feet, knee, step, trial)
            print(json.dumps({k: v for k, v in row.items() if k != "directions"}), flush=True)
            out.write(json.dumps(row) + "\n")
            out.flush()


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--out", type=Path, default=Path("docs/data/feet_floor.jsonl"))
    ap.add_argument("--models", default=",".join(c[0] for c in CANDIDATES))
    ap.add_argument("--trials", default="", help="SUBJECT:CODE,... to measure (default: every shipped trial)")
    ap.add_argument("--timing", action="store_true", help="time cold solves instead of measuring fits")
    ap.add_argument("--table", action="store_true", help="only print the tables of the results in --out")
    args = ap.parse_args()
    labels = args.models.split(",")
    if not args.table:
        args.out.parent.mkdir(parents=True, exist_ok=True)
        with args.out.open("a") as f:
            if args.timing:
                for row in timing(labels):
                    f.write(json.dumps(row) + "\n")
            else:
                data = WbdsData()
                every = [(sub, code) for sub in data.subjects() for code in data.speeds(sub)]
                chosen = [tuple(t.split(":")) for t in args.trials.split(",")] if args.trials else every
                for subject, code in chosen:
                    _measure(data.trial(subject, code), labels, f)
    print(table(args.out))


if __name__ == "__main__":
    main()
