"""Gait-regime study: a step-length sweep of the forward problem (docs/gait_regime.md).

For every lift-off rule (the paper's zero-velocity lift-off, or the relaxed one), every
weighting (the nominal weights on dimensionless features, or on features in "g-units",
i.e. a 1 m, 1 kg walker under g = 9.81), both speeds and step lengths 0.1 .. 0.9 leg
lengths: the best of ``--starts`` starts with the step length held; its cost, features,
duration, cadence, swing-foot clearance and active bounds. Then the step length is
released and the solve is warm-started from that optimum, once under the paper's cost
(summed over the step) and once under the cost per unit time: where does the step go?

    python studies/gait_regime.py --out docs/data/gait_regime.json
    python studies/gait_regime.py --plot docs/data/gait_regime.json --figure docs/figures/gait_regime.png
"""

from __future__ import annotations

import argparse
import itertools
import json
import multiprocessing as mp
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

import numpy as np

from ioc_bench.features import ALL_FEATURES, PAPER_GRAVITY, TIME_UNIT, evaluate
from ioc_bench.fileio import atomic_write_json
from ioc_bench.model.gait_model import GuessShape
from ioc_bench.model.params import WalkerParams
from ioc_bench.model.walker import WALKER
from ioc_bench.task import Task
from ioc_bench.trajopt.forward_problem import SolveRequest, get_forward_problem
from ioc_bench.trajopt.gait_figures import gait_figures
from ioc_bench.trajopt.initial_guess import perturbed_step, rough_step
from ioc_bench.trajopt.solution import StartPoint
from ioc_bench.trajopt.step_problem import StepRules

#: Exponent of g in each cost feature's per-step sum (torque^2 time; (torque/time)^2 time):
#: the factor between its value in g-units and in dimensionless units.
G_POWER = {"hip": 1.5, "knee": 1.5, "dtau": 2.5}
STEP_LENGTHS = tuple(round(0.1 * k, 1) for k in range(1, 10))
SPEEDS = (0.27, 0.34)


def weights_for(units: str) -> np.ndarray:
    """Nominal weights (1, 1, 1) over ALL_FEATURES, on features in ``units``, as weights on
    the features the solver computes (which are in g-units)."""
    scale = np.array([1.0 if units == "g" else PAPER_GRAVITY ** -G_POWER[f] for f in ("hip", "knee", "dtau")])
    w = np.zeros(len(ALL_FEATURES))
    w[:3] = scale / np.linalg.norm(scale)
    return w


def figures(traj, params, speed: float, active=None) -> dict:
    f = gait_figures(WALKER, params, traj, Task(speed), active)
    return {
        "step_length": f.step_length,
        "duration": f.duration,
        "cadence": f.cadence,
        "max_clearance": f.max_clearance,
        "mid_swing_min_clearance": f.mid_swing_clearance,
        "peak_torque": max(f.peak_torques.values()),
        "active": f.active,
    }


def solve_held(forward, params, rules, w, speed: float, length: float, starts: int, extra=()) -> list:
    """Solves of the step held at ``length``: rough and perturbed guesses, plus ``extra`` starts."""
    base = GuessShape(step=length)
    guesses = [rough_step(WALKER, params, speed, forward.n_knots, base)] if starts else []
    guesses += [
        perturbed_step(WALKER, params, speed, forward.n_knots, np.random.default_rng([11, i]), base)
        for i in range(1, starts)
    ]
    points = [StartPoint(forward.step.layout.pack(g)) for g in guesses] + list(extra)
    return [forward.solve(SolveRequest(p, params, Task(speed, length), w, rules=rules)) for p in points]


def describe(forward, best, params, rules, w, speed: float, length: float) -> dict:
    phi = evaluate(best.trajectory, params)
    seconds = TIME_UNIT * best.trajectory.duration
    active = forward.active_bounds(best.x, params, Task(speed, length), rules)
    out = {
        "features": phi,
        "per_step_g": {f: phi[f] * seconds for f in G_POWER},
        "figures": figures(best.trajectory, params, speed, active),
        "cost_per_time": float(w[:3] @ [phi[f] for f in G_POWER]),
    }
    out["cost_per_step"] = out["cost_per_time"] * seconds
    for cost in ("per-step", "per-time"):
        r = forward.solve(SolveRequest(best.point, params, Task(speed), w, rules=StepRules(rules.liftoff, cost)))
        free = {"status": r.report.status, "success": r.report.success}
        if r.report.success:
            free |= figures(r.trajectory, params, speed) | {"cost": r.report.objective}
        out[f"released_{cost}"] = free
    return out


def run_chain(cfg: tuple) -> list[dict]:
    """One (lift-off, units, speed) chain over every step length, with continuation: each
    length also starts from its neighbours' optima (one pass up, one down)."""
    liftoff, units, speed, starts = cfg
    forward = get_forward_problem()
    params, rules, w = WalkerParams(), StepRules(liftoff=liftoff, cost="per-step"), weights_for(units)
    best: dict[float, object] = {}

    def keep(length, results):
        ok = [r for r in results if r.report.success]
        if length in best:
            ok.append(best[length])
        if ok:
            best[length] = min(ok, key=lambda r: r.report.objective)

    for i, length in enumerate(STEP_LENGTHS):
        extra = [StartPoint(best[STEP_LENGTHS[i - 1]].x)] if i and STEP_LENGTHS[i - 1] in best else []
        keep(length, solve_held(forward, params, rules, w, speed, length, starts, extra))
    for i in range(len(STEP_LENGTHS) - 2, -1, -1):
        length, above = STEP_LENGTHS[i], STEP_LENGTHS[i + 1]
        if above in best:
            keep(length, solve_held(forward, params, rules, w, speed, length, 0, [StartPoint(best[above].x)]))
    rows = []
    for length in STEP_LENGTHS:
        row = {"liftoff": liftoff, "units": units, "speed": speed, "held_step": length}
        if length in best:
            row |= describe(forward, best[length], params, rules, w, speed, length)
        rows.append(row)
    return rows


def sweep(starts: int, workers: int) -> list[dict]:
    get_forward_problem()  # built once; forked workers inherit it
    chains = list(itertools.product(("paper", "relaxed"), ("g", "dimensionless"), SPEEDS, [starts]))
    rows: list[dict] = []
    with ProcessPoolExecutor(workers, mp_context=mp.get_context("fork")) as pool:
        for i, chain in enumerate(pool.map(run_chain, chains)):
            rows += chain
            print(f"{i + 1}/{len(chains)} chains done", flush=True)
    return rows


def plot(rows: list[dict], path: Path) -> Path:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    paper = {"hip": 0.0975, "knee": 0.0809, "dtau": 0.0142}
    fig, axes = plt.subplots(2, 4, figsize=(16, 7), sharex=True)
    styles = {
        ("paper", "g"): "-",
        ("relaxed", "g"): "--",
        ("paper", "dimensionless"): ":",
        ("relaxed", "dimensionless"): "-.",
    }
    colors = {0.27: "C0", 0.34: "C3"}
    for (liftoff, units), ls in styles.items():
        for speed in SPEEDS:
            sel = [
                r for r in rows if (r["liftoff"], r["units"], r["speed"]) == (liftoff, units, speed) and "features" in r
            ]
            if not sel:
                continue
            L = [r["held_step"] for r in sel]
            lab = f"{liftoff} lift-off, {units} weights, v={speed}"
            kw = {"ls": ls, "color": colors[speed], "label": lab}
            if units == "g":
                for ax, f in zip(axes[0, :3], ("hip", "knee", "dtau")):
                    ax.plot(L, [r["per_step_g"][f] for r in sel], **kw)
            axes[0, 3].plot(L, [r["cost_per_time"] / sel[0]["cost_per_time"] for r in sel], **kw)
            axes[1, 0].plot(L, [r["cost_per_step"] / sel[0]["cost_per_step"] for r in sel], **kw)
            axes[1, 1].plot(L, [r["figures"]["mid_swing_min_clearance"] for r in sel], **kw)
            for ax, cost in zip(axes[1, 2:], ("per-step", "per-time")):
                ax.plot(L, [r[f"released_{cost}"].get("step_length", np.nan) for r in sel], marker="o", **kw)
    for ax, f in zip(axes[0, :3], ("hip", "knee", "dtau")):
        ax.axhline(paper[f], color="k", lw=0.8)
        ax.set_yscale("log")
        ax.set_title(f"phi_{f} per step, g-units (black: paper)")
    axes[0, 3].set_title("cost per time / cost per time at L=0.1")
    axes[1, 0].set_title("cost per step / cost per step at L=0.1")
    axes[1, 1].set_title("mid-swing minimum foot height")
    for ax, cost in zip(axes[1, 2:], ("per-step", "per-time")):
        ax.plot([0.1, 0.9], [0.1, 0.9], color="grey", lw=0.5)
        ax.set_title(f"step length after release ({cost} cost)")
    for ax in axes[1]:
        ax.set_xlabel("held step length (leg lengths)")
    axes[0, 3].legend(fontsize=6)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    return path


def tables(rows: list[dict]) -> str:
    """The sweep as Markdown: one table per (lift-off, weighting), both speeds."""
    paper = {"hip": 0.0975, "knee": 0.0809, "dtau": 0.0142}
    out = []
    for liftoff, units in itertools.product(("paper", "relaxed"), ("g", "dimensionless")):
        out += [
            f"### {liftoff} lift-off, nominal weights on {'g-unit' if units == 'g' else 'dimensionless'} features",
            "",
            "| speed | held step | per-step sums hip / knee / dtau (g-units; ratio to the paper) | cost per step "
            "| cost per time | duration | cadence (0.9 m leg) | max / mid-swing foot height | active bounds "
            "(not idle) | released: per-step cost | released: per-time cost |",
            "|---|---|---|---|---|---|---|---|---|---|---|",
        ]
        for r in rows:
            if (r["liftoff"], r["units"]) != (liftoff, units):
                continue
            if "features" not in r:
                out.append(f"| {r['speed']} | {r['held_step']} | no feasible start | | | | | | | | |")
                continue
            f, s = r["figures"], r["per_step_g"]
            feats = " / ".join(f"{s[k]:.3g} ({s[k] / paper[k]:.2f})" for k in ("hip", "knee", "dtau"))
            active = {k: v for kind in ("physical", "artificial") for k, v in f["active"][kind].items()}
            act = ", ".join(f"{k} {v}" for k, v in active.items()) or "-"
            rel = [r[f"released_{c}"] for c in ("per-step", "per-time")]
            rel_txt = [f"{x['step_length']:.3f}" if x.get("success") else x["status"] for x in rel]
            out.append(
                f"| {r['speed']} | {r['held_step']} | {feats} | {r['cost_per_step']:.3g} | {r['cost_per_time']:.3g} "
                f"| {f['duration']:.2f} | {f['cadence']:.0f} | {f['max_clearance']:.3f} / "
                f"{f['mid_swing_min_clearance']:.4f} | {act} | {rel_txt[0]} | {rel_txt[1]} |"
            )
        out.append("")
    return "\n".join(out)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--out", type=Path, default=Path("docs/data/gait_regime.json"))
    ap.add_argument("--starts", type=int, default=4)
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--plot", type=Path, help="only plot this JSON")
    ap.add_argument("--figure", type=Path, default=Path("docs/figures/gait_regime.png"))
    ap.add_argument("--tables", type=Path, help="only print the Markdown tables of this JSON")
    args = ap.parse_args()
    if args.tables:
        print(tables(json.loads(args.tables.read_text())))
        return
    if args.plot:
        print(plot(json.loads(args.plot.read_text()), args.figure))
        return
    rows = sweep(args.starts, args.workers)
    atomic_write_json(args.out, rows)
    print(args.out, plot(rows, args.figure))


if __name__ == "__main__":
    main()
