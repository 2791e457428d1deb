"""Human steps against the subject's walker: does it solve each human task, and how close
do its optima come to the person's step (docs/human.md)?

For each WBDS trial (subject, treadmill speed): the subject's walker and the trial's task
(speed and step length from the laboratory's table). First the nominal weights with 2 and
4 starts, each step checked as a local minimum (the benchmark's standard): success, IPOPT
iterations over all starts, wall time. Then a grid of weight directions over (hip, knee,
dtau), 2 starts each, no local-minimum check (to keep the budget modest): the RMSE in
degrees of the four leg segments' angles between the walker's optimum and the person's
step, and of the ground force (both feet of the person against the walker's stance foot,
body weights). Results are appended to the JSON as they come (rerunning resumes).

    python studies/human_steps.py --subjects WBDS01 --out docs/data/human_steps.json
    python studies/human_steps.py --subjects WBDS01 --probes docs/data/human_steps.json
    python studies/human_steps.py --subjects WBDS01 --basins docs/data/human_steps.json
    python studies/human_steps.py --compact docs/data/human_steps.json
    python studies/human_steps.py --tables docs/data/human_steps.json
    python studies/human_steps.py --figure docs/figures/human_steps.png --subject WBDS01 docs/data/human_steps.json
    python studies/human_steps.py --basin-figure docs/figures/human_basins.png

One core; about 10 minutes per subject on a loaded 2-core machine.
"""

from __future__ import annotations

import argparse
import dataclasses
import itertools
import json
import time
from pathlib import Path

import numpy as np

from ioc_bench.fileio import atomic_write_json
from ioc_bench.human import WbdsData, human_step, segment_rmse_deg, walker_ground_force
from ioc_bench.human.observe import leg_angles
from ioc_bench.model.params import WalkerParams
from ioc_bench.optimize import optimize_gait
from ioc_bench.weights import normalize, parse_weights

SPEEDS = ("T03", "T04", "T05", "T06")
#: Nominal solves: (starts, local-minimum check).
NOMINAL_RUNS = ((2, True), (4, True))
GRID_STARTS = 2
LATTICE = 5


def directions() -> dict[str, list[float]]:
    """The simplex lattice (a, b, c) with a + b + c = 5 over (hip, knee, dtau), plus the
    nominal (1, 1, 1); each normalised to unit length (21 + 1 directions)."""
    out = {"nominal": normalize([1.0, 1.0, 1.0]).tolist()}
    for a, b in itertools.product(range(LATTICE + 1), repeat=2):
        c = LATTICE - a - b
        if c >= 0:
            out[f"{a},{b},{c}"] = normalize([a, b, c]).tolist()
    return out


def solve(step, weights, starts: int, verify: bool) -> dict:
    t0 = time.perf_counter()
    demo = optimize_gait(weights, step.params, step.task, starts=starts, seed=0, workers=1, verify=verify)
    wall = time.perf_counter() - t0
    traj = demo.trajectory
    force = walker_ground_force(traj)
    human = step.forces.total
    record = {
        "weights": [round(float(w), 6) for w in demo.weight_vector[:3]],
        "starts": starts,
        "verified": verify,
        "success": bool(demo.solver.success),
        "status": demo.solver.status,
        "objective": float(demo.solver.objective),
        "iterations": int(sum(s.report.iterations for s in demo.multistart.starts)) if demo.multistart else None,
        "wall_s": round(wall, 2),
        "local_minimum": None if demo.local_minimum is None else bool(demo.local_minimum.passed),
        "rmse_deg": round(segment_rmse_deg(traj, step), 3),
        "force_rmse_bw": [round(float(np.sqrt(np.mean((force[:, k] - human[:, k]) ** 2))), 4) for k in (0, 1)],
        "angles": np.round(leg_angles(traj), 4).tolist(),
        "force": np.round(force, 3).tolist(),
    }
    return record


#: Probes beside the grid: (walker, label, weights, starts). "default" is the benchmark's
#: walker (docs/spec.md, "Segment parameters"), not scaled to the person.
PROBES = (
    ("default", "nominal", (1.0, 1.0, 1.0), 2),
    ("default", "1,4,0", (1.0, 4.0, 0.0), 2),
    ("default", "0.30,0.95,0.05", (0.30, 0.95, 0.05), 4),
    ("default", "0,0,5", (0.0, 0.0, 5.0), 2),
    ("subject", "0.30,0.95,0.05", (0.30, 0.95, 0.05), 4),
    ("subject", "1,4,0", (1.0, 4.0, 0.0), 4),
    ("subject", "0,0,5", (0.0, 0.0, 5.0), 4),
    ("subject", "1,0,4", (1.0, 0.0, 4.0), 4),
)


def probe(subjects: list[str], out: Path) -> None:
    """The :data:`PROBES` for each trial (after :func:`run`), appended under ``probes``."""
    results = json.loads(out.read_text())
    data = WbdsData()
    for subject, speed in itertools.product(subjects, SPEEDS):
        step = human_step(data.trial(subject, speed))
        entry = results[f"{subject}/{speed}"].setdefault("probes", {})
        for walker, label, weights, starts in PROBES:
            key = f"{walker}/{label}/{starts}"
            if key in entry:
                continue
            params = WalkerParams() if walker == "default" else step.params
            entry[key] = solve(dataclasses.replace(step, params=params), weights, starts, False)
            rec = entry[key]
            print(f"{subject} {speed} {key}: {rec['status']} {rec['rmse_deg']:.2f} deg {rec['wall_s']} s", flush=True)
            atomic_write_json(out, results)


#: Basins: every start of an 8-start solve, its cost and its fit (trials, weights).
BASIN_TRIALS = ("T03", "T05", "T06")
BASIN_WEIGHTS = {"nominal": (1.0, 1.0, 1.0), "1,4,0": (1.0, 4.0, 0.0)}
BASIN_STARTS = 8


def basins(subjects: list[str], out: Path) -> None:
    """Per start of an 8-start multi-start (starts are nested: the first 2 and 4 are those
    of a 2- and 4-start solve): status, objective, fit. Does a cheaper optimum fit better?"""
    from ioc_bench.trajopt.solver import StartPoint, get_solver

    from ioc_bench.features import model_features
    from ioc_bench.model.walker import WALKER
    from ioc_bench.trajopt.initial_guess import multistart_guesses
    from ioc_bench.trajopt.multistart import solve_starts
    from ioc_bench.trajopt.step_problem import DEFAULT_INTERVALS

    results = json.loads(out.read_text())
    data = WbdsData()
    layout = get_solver(DEFAULT_INTERVALS, WALKER).nlp.layout
    for subject, speed in itertools.product(subjects, BASIN_TRIALS):
        step = human_step(data.trial(subject, speed))
        entry = results[f"{subject}/{speed}"].setdefault("basins", {})
        for label, weights in BASIN_WEIGHTS.items():
            if label in entry:
                continue
            tried = multistart_guesses(
                WALKER, step.params, step.task.speed, step.task.step_length, 2 * DEFAULT_INTERVALS + 1, BASIN_STARTS, 0
            )
            points = [StartPoint(layout.pack(blocks)) for _, blocks in tried]
            t0 = time.perf_counter()
            w = parse_weights(weights, model_features(WALKER))
            solved = solve_starts(points, step.params, step.task, w, DEFAULT_INTERVALS, workers=1)
            entry[label] = {
                "wall_s": round(time.perf_counter() - t0, 1),
                "starts": [
                    {
                        "success": bool(r.report.success),
                        "objective": float(r.report.objective),
                        "iterations": int(r.report.iterations),
                        "rmse_deg": round(segment_rmse_deg(r.trajectory, step), 3),
                    }
                    for r in solved
                ],
            }
            line = ", ".join(f"{x['objective']:.4f}:{x['rmse_deg']:.1f}" for x in entry[label]["starts"])
            print(f"{subject} {speed} {label}: {line}", flush=True)
            atomic_write_json(out, results)


def run(subjects: list[str], out: Path) -> None:
    results = json.loads(out.read_text()) if out.exists() else {}
    data = WbdsData()
    grid = directions()
    for subject, speed in itertools.product(subjects, SPEEDS):
        step = human_step(data.trial(subject, speed))
        entry = results.setdefault(f"{subject}/{speed}", {"trial": _trial_record(step), "solves": {}})
        todo = [(f"nominal/{s}/{'verified' if v else 'plain'}", "nominal", s, v) for s, v in NOMINAL_RUNS]
        todo += [(f"grid/{name}", w, GRID_STARTS, False) for name, w in grid.items()]
        for key, weights, starts, verify in todo:
            if key in entry["solves"]:
                continue
            entry["solves"][key] = solve(step, weights, starts, verify)
            rec = entry["solves"][key]
            print(f"{subject} {speed} {key}: {rec['status']} {rec['rmse_deg']:.2f} deg {rec['wall_s']} s", flush=True)
            atomic_write_json(out, results)


def _trial_record(step) -> dict:
    c = step.checks
    return {
        "leg_length_m": round(step.body.leg_length, 4),
        "speed": round(step.task.speed, 4),
        "step_length": round(step.task.step_length, 4),
        "duration": round(step.duration, 4),
        "cadence_spm": round(60.0 / (step.duration * step.body.time_unit), 2),
        "params": step.params.to_dict(),
        "checks": {k: (None if v is None else round(float(v), 4)) for k, v in vars(c).items()},
        "notes": c.notes(),
        "angles": np.round(step.angles, 4).tolist(),
        "force": np.round(step.forces.total, 3).tolist(),
    }


# -- tables and figure ---------------------------------------------------------------------


def _grid(entry: dict) -> dict[str, dict]:
    return {k.split("/", 1)[1]: v for k, v in entry["solves"].items() if k.startswith("grid/")}


def _best(entry: dict) -> tuple[str, dict]:
    ok = {k: v for k, v in _grid(entry).items() if v["success"]}
    name = min(ok, key=lambda k: ok[k]["rmse_deg"])
    return name, ok[name]


def interval_means(force) -> np.ndarray:
    """(M, 2) each Hermite-Simpson interval's mean force (Simpson weights 1, 4, 1 over its
    knots and midpoint): the walker's midpoint pin forces alternate near heel strike, their
    interval means (impulse over duration) do not."""
    f = np.asarray(force, dtype=float)
    return (f[0:-1:2] + 4 * f[1::2] + f[2::2]) / 6


def _force_rmse(walker, human) -> tuple[float, float]:
    """Vertical force RMSE (body weights) of the interval means: all intervals, and without
    the first and last (the walker's impact transient on a rigid point foot)."""
    d = interval_means(walker)[:, 1] - interval_means(human)[:, 1]
    return float(np.sqrt(np.mean(d**2))), float(np.sqrt(np.mean(d[1:-1] ** 2)))


def tables(path: Path) -> None:
    results = json.loads(path.read_text())
    print("### The human tasks and the subject's walker\n")
    print(
        "| trial | leg (m) | speed | step (L) | cadence | stance knee flexion (deg) | least knee flexion | "
        "double support (% of step) | pose step / table step | trend step | R-L asymmetry (deg) |"
    )
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for key, entry in results.items():
        t, c = entry["trial"], entry["trial"]["checks"]
        trend = "-" if c["trend_step_length"] is None else f"{c['trend_step_length']:.3f}"
        print(
            f"| {key} | {t['leg_length_m']:.3f} | {t['speed']:.3f} | {t['step_length']:.3f} | {t['cadence_spm']:.0f} | "
            f"{c['stance_knee_flexion_deg']:.1f} | {c['min_knee_flexion_deg']:.1f} | "
            f"{100 * c['double_support_step']:.0f} | "
            f"{c['pose_step_length'] / c['table_step_length']:.2f} | {trend} | {c['asymmetry_deg']:.1f} |"
        )
    print("\n### Nominal weights: solving each task\n")
    print("| trial | starts | status | local minimum | IPOPT iterations (all starts) | wall (s) | RMSE (deg) |")
    print("|---|---|---|---|---|---|---|")
    for key, entry in results.items():
        for name, rec in entry["solves"].items():
            if name.startswith("nominal/"):
                print(
                    f"| {key} | {rec['starts']} | {rec['status']} | {rec['local_minimum']} | {rec['iterations']} | "
                    f"{rec['wall_s']:.1f} | {rec['rmse_deg']:.2f} |"
                )
    print("\n### Weight grid (2 starts, 22 directions): fit of the leg segment angles\n")
    print(
        "| trial | failed solves | nominal RMSE (deg) | best RMSE (deg) | best lattice point (hip, knee, dtau) | "
        "best weights (unit) | within 0.5 deg of best | vertical force RMSE (BW), nominal -> best: "
        "all intervals / without the first and last |"
    )
    print("|---|---|---|---|---|---|---|---|")
    for key, entry in results.items():
        grid = _grid(entry)
        if not grid:
            continue
        name, best = _best(entry)
        nominal = grid["nominal"]
        failed = sum(not v["success"] for v in grid.values())
        near = sorted(k for k, v in grid.items() if v["success"] and v["rmse_deg"] <= best["rmse_deg"] + 0.5)
        w = ", ".join(f"{x:.2f}" for x in best["weights"])
        human = entry["trial"]["force"]
        fn, fb = (_force_rmse(rec["force"], human) for rec in (nominal, best))
        print(
            f"| {key} | {failed} | {nominal['rmse_deg']:.2f} | {best['rmse_deg']:.2f} | {name} | {w} | "
            f"{'; '.join(near)} | {fn[0]:.2f} / {fn[1]:.2f} -> {fb[0]:.2f} / {fb[1]:.2f} |"
        )
    probe_table(results)
    basin_table(results)


def probe_table(results: dict) -> None:
    print("\n### Probes: the default walker, and more starts\n")
    keys = sorted({k for e in results.values() for k in e.get("probes", {})})
    if not keys:
        return
    print("| trial | " + " | ".join(keys) + " |")
    print("|---|" + "---|" * len(keys))
    for name, entry in results.items():
        probes = entry.get("probes", {})
        if not probes:
            continue
        cells = []
        for k in keys:
            rec = probes.get(k)
            cells.append("-" if rec is None else f"{rec['rmse_deg']:.2f}" + ("" if rec["success"] else " (failed)"))
        print(f"| {name} | " + " | ".join(cells) + " |")


def basin_table(results: dict) -> None:
    rows = [(k, label, b) for k, e in results.items() for label, b in e.get("basins", {}).items()]
    if not rows:
        return
    print("\n### Basins: each start of an 8-start solve (objective, RMSE in deg); * = chosen by 2, 4, 8 starts\n")
    print("| trial | weights | starts (objective : RMSE) | best of 2 / 4 / 8 starts: RMSE | lowest RMSE |")
    print("|---|---|---|---|---|")
    for key, label, b in rows:
        st = b["starts"]
        picks = []
        for n in (2, 4, 8):
            ok = [i for i in range(n) if st[i]["success"]]
            picks.append(min(ok, key=lambda i: st[i]["objective"]) if ok else None)
        cells = ", ".join(
            f"{x['objective']:.4f} : {x['rmse_deg']:.1f}" + ("" if x["success"] else " (failed)") for x in st
        )
        chosen = " / ".join("-" if i is None else f"{st[i]['rmse_deg']:.1f}" for i in picks)
        lowest = min(x["rmse_deg"] for x in st if x["success"])
        print(f"| {key} | {label} | {cells} | {chosen} | {lowest:.1f} |")


def figure(path: Path, subject: str, out: Path) -> None:
    from ioc_bench.human.figures import plot_human_fits

    results = json.loads(path.read_text())
    panels = []
    for speed in SPEEDS:
        entry = results.get(f"{subject}/{speed}")
        if entry is None or not _grid(entry):
            continue
        name, best = _best(entry)
        nominal = _grid(entry)["nominal"]
        trial = entry["trial"]
        panels.append(
            {
                "title": f"{subject} {speed} (v {trial['speed']:.2f}, step {trial['step_length']:.2f} L)",
                "human": np.array(entry["trial"]["angles"]),
                "walkers": {
                    f"nominal ({nominal['rmse_deg']:.1f} deg)": np.array(nominal["angles"]),
                    f"best {name} ({best['rmse_deg']:.1f} deg)": np.array(best["angles"]),
                },
            }
        )
    print(plot_human_fits(panels, out))


def basin_figure(out: Path, subject: str = "WBDS01", speed: str = "T05", weights=(1.0, 4.0, 0.0)) -> None:
    """Starts 0 and 2 of the basin study re-solved: the human-like optimum and the cheaper
    one that lands on a bent knee."""
    from ioc_bench.trajopt.solver import StartPoint, get_solver

    from ioc_bench.features import model_features
    from ioc_bench.human.figures import plot_human_fits
    from ioc_bench.model.walker import WALKER
    from ioc_bench.trajopt.initial_guess import multistart_guesses
    from ioc_bench.trajopt.multistart import solve_starts
    from ioc_bench.trajopt.step_problem import DEFAULT_INTERVALS

    step = human_step(WbdsData().trial(subject, speed))
    layout = get_solver(DEFAULT_INTERVALS, WALKER).nlp.layout
    n_knots = 2 * DEFAULT_INTERVALS + 1
    tried = multistart_guesses(WALKER, step.params, step.task.speed, step.task.step_length, n_knots, 3, 0)
    points = [StartPoint(layout.pack(blocks)) for _, blocks in tried][::2]
    w = parse_weights(weights, model_features(WALKER))
    walkers = {}
    for i, r in zip((0, 2), solve_starts(points, step.params, step.task, w, DEFAULT_INTERVALS, workers=1)):
        knee = np.degrees(r.trajectory.q[0, 2, 2] - r.trajectory.q[0, 1, 2])
        label = f"start {i}: cost {r.report.objective:.2f}, {segment_rmse_deg(r.trajectory, step):.1f} deg"
        walkers[f"{label}, knee at heel strike {knee:.0f} deg"] = leg_angles(r.trajectory)
    title = f"{subject} {speed}, weights {weights}"
    print(plot_human_fits([{"title": title, "human": step.angles, "walkers": walkers}], out))


def compact(path: Path) -> None:
    """Drop the per-knot arrays of every solve but each trial's grid nominal and grid best
    (what the tables and figures read), to keep the committed JSON small."""
    results = json.loads(path.read_text())
    for entry in results.values():
        keep = set()
        if _grid(entry):
            keep = {"grid/nominal", f"grid/{_best(entry)[0]}"}
        for group in ("solves", "probes"):
            for key, rec in entry.get(group, {}).items():
                if not (group == "solves" and key in keep):
                    rec.pop("angles", None)
                    rec.pop("force", None)
    atomic_write_json(path, results)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("json", nargs="?", type=Path, help="results to tabulate or plot (with --tables/--figure)")
    parser.add_argument("--subjects", nargs="+", default=["WBDS01"])
    parser.add_argument("--out", type=Path, help="solve and append results here")
    parser.add_argument("--probes", type=Path, help="run the probes and append them here (after --out)")
    parser.add_argument("--basins", type=Path, help="run the basin study and append it here (after --out)")
    parser.add_argument("--compact", type=Path, help="drop per-knot arrays not needed by tables and figures")
    parser.add_argument("--tables", type=Path)
    parser.add_argument("--figure", type=Path)
    parser.add_argument("--subject", default="WBDS01")
    parser.add_argument("--basin-figure", type=Path, help="re-solve two starts of the basin study and plot them")
    args = parser.parse_args()
    if args.out:
        run(args.subjects, args.out)
    if args.probes:
        probe(args.subjects, args.probes)
    if args.basins:
        basins(args.subjects, args.basins)
    if args.compact:
        compact(args.compact)
    if args.tables:
        tables(args.tables)
    if args.figure:
        figure(args.json, args.subject, args.figure)
    if args.basin_figure:
        basin_figure(args.basin_figure)


if __name__ == "__main__":
    main()
