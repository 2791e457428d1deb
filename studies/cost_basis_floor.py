"""Does a richer cost basis let the walker step like a person? (the cost-basis floor)

For each shipped subject (WBDS01-03) and trial T03-T06 (12 trials), at the trial's speed
with the step length free (the human track's ``speed`` task: ``Task(step.task.speed)``),
for each cell of

- model: ``walker`` (the subject's walker, point feet and knee-lock, as the human track
  maps a person) or ``ankle`` (the same subject's lengths through Winter's table on feet with
  actuated ankles, free knee: ``footed_params(..., "ankle", "free")``, as
  ``studies/feet_floor.py`` builds it, the catalogue's ``ankle-feet`` on the subject's body;
  the human track itself has no mapping onto it), and
- basis: ``effort`` (the model's ``cost_features``: hip, knee, dtau; plus ankle on the
  ankle model) or ``rich`` (effort + ``work`` + ``collision``, ``ioc_bench/features.py``),

it measures:

- **the floor over the basis**: the optimal step of every weight direction of a simplex
  lattice over the basis (integer points summing to ``--divisions``; with the default 2:
  walker 6 (effort) and 15 (rich) directions, ankle 10 and 21), each solved from ``--starts``
  seeded starts (the rough guess and perturbed ones whose step lengths spread over 0.2-0.8
  leg lengths, ``multistart_guesses``; the cheapest feasible optimum kept, ``pick_best``:
  what ``optimize_gait(..., workers=1, verify=False)`` does, which cannot take the study's
  ankle model because multi-start workers look models up in the catalogue by name). Per
  direction: the weights, the kept optimum's leg-angle RMSE to the person (deg, four leg
  segments, the human track's metric), its step length against the person's (``|log|``
  ratio, the human track's step-length error), the feature values there, its status, the
  solves, iterations and seconds. The cell's floor is the lowest RMSE over the directions.
  With equal divisions the rich lattice holds every effort direction (work and collision at
  0), solved from the same starts: those directions repeat the effort cell's solves and
  should give its numbers (a check that the rich problem is the same problem there). With 2
  divisions three rich directions weigh no torque at all (work alone, collision alone, the
  two): their optima need not be unique (torques doing negative work cost almost nothing),
  so their solves may be slow or fail; they are kept, pure work being a hypothesis of its own.
- **the projection**: the model's feasible step closest to the person's leg angles (and,
  on the ankle model, foot angles) at the trial's speed and step length, with a vanishing
  effort (``feet_floor.py``'s ``projection``): a lower bound of any cost's RMSE. Made once
  per (subject, trial, model) in a run, with the effort basis.
- **the basis-rejection test**: is the projected person's step an optimum of some
  nonnegative weights of the basis? The inverse-KKT machinery (``fit_kkt``,
  ``ioc_bench/ioc/inverse_kkt.py``) minimises the forward problem's stationarity residual at
  the projected step, at the speed-only task, over nonnegative weights of the basis (unit
  sum in units of each feature's projected gradient), the lock penalty's coefficient and the
  active set's multipliers; ``relative_residual`` is that minimum over the norm of the
  weights' part. A projected step is never exactly optimal (its tracking term and vanishing
  effort shape what the angles leave free), so the scale is the same test on a step that is
  optimal: the cell's best direction's optimum (a synthetic demonstration with known
  weights) is projected exactly as the person is, from its own leg (and foot) angles, and
  tested. Verdict ``rejected`` when the person's residual exceeds :data:`REJECT_FACTOR`
  times the synthetic one's, ``not rejected`` otherwise, ``n/a`` when a projection, every
  direction or a least-squares fit failed. The residual at the optimum itself (before
  projection) and the weights it recovers are recorded as a check of the machinery.

Output: one JSON line per finished (subject, trial, model, basis), appended in one write
to ``--out``; a unit already there (same divisions, starts and seed) is skipped, so a run
resumes where it stopped and can be split with ``--subjects``, ``--trials``, ``--models``
and ``--bases``. A line per finished unit goes to stderr. ``--plan`` lists what is left with
its solve count and time estimate (no solve, no build); ``--table`` prints the summary of
the file, ending with each trial's floors side by side: the effort unit's, the rich unit's
over its effort directions only (the effort cell's problems, inside the rich basis, from the
same starts), and the rich unit's, with their medians over the trials where every model's
rich unit ran. Where a model's effort unit has not run (the ankle model's solves cost about
7x the walker's), its effort floor is read from the rich unit that way; its rejection test is not.

Solves with the defaults (``--divisions 2 --starts 8``): per unit, directions x starts plus
two projections (the synthetic optimum's, and the person's, which the bases of one run share;
a failed projection's retry adds one):

    cell            directions  solves per trial  solves, 12 trials  estimate on 1 core
    walker effort        6             50                600           15-30 min
    walker rich         15            122               1464           40-75 min
    ankle effort        10             82                984           4.1-5.5 h
    ankle rich          21            170               2040           8.5-11.3 h
    all                                                 5088           about 14-18 h

The times are an estimate: the solves times :data:`SECONDS_PER_SOLVE` (walker 1.5-3 s a
cold solve with the step length free: ``human_step_lengths.py`` takes ~3 min for 135, and
the walker's rich units took 2.2-3.2 s a solve; ankle 17.8-18.5 s a solve in its first two
rich units, two processes side by side, 50-52 min a unit, where half the starts end
infeasible: docs/notes/2026-12-08-cost-basis-and-ankles.md), plus some seconds per problem
built. ``--plan`` prints the same for what is left. Parts under an hour each on
one core, e.g.:

    python studies/cost_basis_floor.py --models walker --bases effort                       # ~15-30 min
    python studies/cost_basis_floor.py --models walker --bases rich --subjects WBDS01       # ~12-25 min
    python studies/cost_basis_floor.py --models ankle --bases effort --subjects WBDS01 --trials T03,T04  # ~41-56 min
    python studies/cost_basis_floor.py --models ankle --bases rich --subjects WBDS01 --trials T03        # ~43-58 min
    python studies/cost_basis_floor.py --plan                                                # what is left
    python studies/cost_basis_floor.py --table

Two such parts may run at once (one per core) on the same ``--out``: each line is one
``write`` to a file opened for appending.
"""

from __future__ import annotations

import argparse
import importlib.util
import itertools
import json
import math
import os
import statistics
import sys
import time
from collections.abc import Iterable, Sequence
from pathlib import Path
from types import SimpleNamespace
from typing import Any

import numpy as np

from ioc_bench.bases import get_basis
from ioc_bench.model.feet import ANKLE_FEET, footed_model, footed_params
from ioc_bench.model.gait_model import GaitModel, GuessShape
from ioc_bench.model.walker import WALKER
from ioc_bench.task import Task

#: The shipped subjects and the trials of each (4 speeds).
SUBJECTS = ("WBDS01", "WBDS02", "WBDS03")
TRIALS = ("T03", "T04", "T05", "T06")
MODELS = ("walker", "ankle")
BASES = ("effort", "rich")
#: The package's cost basis (``ioc_bench/bases.py``) behind each of the study's labels.
PACKAGE_BASIS = {"effort": "effort", "rich": "energetics"}
#: The person's projected step is rejected when its KKT residual exceeds this many times the
#: residual of a projected optimum (the same test on a step that is optimal for the basis).
REJECT_FACTOR = 10.0
#: Estimated seconds of one cold solve on one core, (low, high), for ``--plan``.
SECONDS_PER_SOLVE = {"walker": (1.5, 3.0), "ankle": (15.0, 20.0)}
#: Estimated seconds to build one forward problem (and its derivatives), for ``--plan``.
SECONDS_PER_BUILD = {"walker": 10.0, "ankle": 20.0}
#: Projections per unit: the person's and the synthetic optimum's.
PROJECTIONS_PER_UNIT = 2
DEFAULT_OUT = Path("docs/data/cost_basis_floor.jsonl")
#: The leg segments the RMSE is over and the feet a model with ankles also tracks.
LEG_SEGMENTS = ("thigh_stance", "shank_stance", "thigh_swing", "shank_swing")
FEET = ("foot_stance", "foot_swing")

#: Each cell's model structure (its features): the catalogue's; each subject's parameters are passed to it.
_TEMPLATES = {"walker": WALKER, "ankle": ANKLE_FEET}


# -- the lattice and the bases (no solver) ------------------------------------------------------
def lattice(n_features: int, divisions: int) -> list[tuple[int, ...]]:
    """The simplex lattice: every tuple of ``n_features`` nonnegative integers summing to
    ``divisions`` (``comb(divisions + n_features - 1, n_features - 1)`` of them)."""
    if n_features < 1 or divisions < 1:
        raise ValueError(f"need at least one feature and one division, got {n_features} and {divisions}")
    return [w for w in itertools.product(range(divisions + 1), repeat=n_features) if sum(w) == divisions]


def lattice_size(n_features: int, divisions: int) -> int:
    return math.comb(divisions + n_features - 1, n_features - 1)


def basis_features(model: str, basis: str) -> tuple[str, ...]:
    """The features of a cell: the model's effort features, and with ``rich`` (the package's
    ``energetics`` basis) work and collision."""
    return get_basis(PACKAGE_BASIS[basis]).features(_TEMPLATES[model])


def unit_solves(model: str, basis: str, divisions: int, starts: int) -> int:
    """Forward solves of one (subject, trial, model, basis): every direction's starts and the
    two projections (at most: the person's is shared by the bases of one run; a failed
    projection's retry from the rough guess adds one)."""
    return lattice_size(len(basis_features(model, basis)), divisions) * starts + PROJECTIONS_PER_UNIT


def direction_label(features: Sequence[str], point: Sequence[int]) -> str:
    """``hip:1 dtau:1``: the lattice point's nonzero entries by feature."""
    return " ".join(f"{f}:{k}" for f, k in zip(features, point) if k)


def verdict(person: float | None, synthetic: float | None, factor: float = REJECT_FACTOR) -> str:
    """``rejected`` when the person's relative KKT residual exceeds ``factor`` times that of
    the projected optimum, ``not rejected`` when not, ``n/a`` when either is missing."""
    if person is None or synthetic is None or not (math.isfinite(person) and math.isfinite(synthetic)):
        return "n/a"
    return "rejected" if person > factor * synthetic else "not rejected"


# -- the file --------------------------------------------------------------------------------------
def unit_key(record: dict[str, Any]) -> tuple:
    return tuple(record[k] for k in ("subject", "trial", "model", "basis", "divisions", "starts", "seed"))


def read_records(path: Path) -> list[dict[str, Any]]:
    """The records of ``path`` (none if it does not exist); an unreadable line is skipped with a note."""
    if not path.exists():
        return []
    out = []
    for n, line in enumerate(path.read_text().splitlines(), 1):
        if not line.strip():
            continue
        try:
            record = json.loads(line)
            unit_key(record)
        except (json.JSONDecodeError, KeyError, TypeError):
            print(f"{path}:{n}: not a record of this study, skipped", file=sys.stderr)
            continue
        out.append(record)
    return out


def append_record(path: Path, record: dict[str, Any]) -> None:
    """Append ``record`` as one JSON line, in one write to a file opened for appending."""
    data = (json.dumps(_jsonable(record), allow_nan=False) + "\n").encode()
    fd = os.open(path, os.O_WRONLY | os.O_APPEND | os.O_CREAT, 0o644)
    try:
        view = memoryview(data)
        while view:
            view = view[os.write(fd, view) :]
        os.fsync(fd)
    finally:
        os.close(fd)


def _jsonable(value: Any) -> Any:
    """Plain JSON values: numpy numbers and arrays as Python's, non-finite floats as None."""
    if isinstance(value, dict):
        return {str(k): _jsonable(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_jsonable(v) for v in value]
    if isinstance(value, np.ndarray):
        return _jsonable(value.tolist())
    if isinstance(value, (bool, np.bool_)):
        return bool(value)
    if isinstance(value, (int, np.integer)):
        return int(value)
    if isinstance(value, (float, np.floating)):
        return float(value) if math.isfinite(value) else None
    return value


# -- the table ---------------------------------------------------------------------------------------
def _median(values: Iterable[float | None]) -> float | None:
    v = [x for x in values if x is not None and math.isfinite(x)]
    return statistics.median(v) if v else None


def _range(values: Iterable[float | None], digits: int = 2) -> str:
    v = [x for x in values if x is not None and math.isfinite(x)]
    if not v:
        return "-"
    return f"{statistics.median(v):.{digits}f} ({min(v):.{digits}f}-{max(v):.{digits}f})"


def _num(value: float | None, fmt: str = ".2f") -> str:
    return "-" if value is None or not math.isfinite(value) else format(value, fmt)


def table(records: Sequence[dict[str, Any]], divisions: int, starts: int, seed: int) -> str:
    """The 2x2 summary and the per-trial rows of the records with these settings."""
    mine = [r for r in records if (r["divisions"], r["starts"], r["seed"]) == (divisions, starts, seed)]
    lines = [f"Cost-basis floor: divisions {divisions}, starts {starts}, seed {seed}; {len(mine)} units"]
    others = len(records) - len(mine)
    if others:
        lines[0] += f" ({others} other units with other settings not shown)"
    cells = {(m, b): [r for r in mine if r["model"] == m and r["basis"] == b] for m in MODELS for b in BASES}
    lines += [
        "",
        "Median over trials of the best direction's leg-angle RMSE, deg (trials):",
        "",
        "| model | " + " | ".join(BASES) + " |",
        "|---|" + "---|" * len(BASES),
    ]
    for m in MODELS:
        row = [f"{_num(_median(r['best']['rmse_deg'] for r in cells[m, b]))} ({len(cells[m, b])})" for b in BASES]
        lines.append(f"| {m} | " + " | ".join(row) + " |")
    lines += [
        "",
        "| model | basis | directions | trials | best RMSE, deg: median (range) | step length |log| error at best: "
        "median | projection RMSE, deg: median | KKT rejection: rejected / tested (n/a) | KKT ratio person / "
        "optimum: median |",
        "|---|---|---|---|---|---|---|---|---|",
    ]
    for (m, b), rows in cells.items():
        if not rows:
            continue
        verdicts = [r["rejection"]["verdict"] for r in rows]
        tested = sum(v != "n/a" for v in verdicts)
        lines.append(
            f"| {m} | {b} | {rows[0]['n_directions']} | {len(rows)} | {_range(r['best']['rmse_deg'] for r in rows)} | "
            f"{_num(_median(r['best']['step_length_error'] for r in rows), '.3f')} | "
            f"{_num(_median(r['projection']['rmse_deg'] for r in rows))} | "
            f"{verdicts.count('rejected')} / {tested} ({len(verdicts) - tested}) | "
            f"{_num(_median(r['rejection']['ratio'] for r in rows), '.3g')} |"
        )
    lines += [
        "",
        "| subject | trial | model | basis | best direction | RMSE, deg | step length walker / person (L) | "
        "|log| error | projection RMSE, deg | KKT residual person / optimum | verdict | failed directions | "
        "solves | s |",
        "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    order = {(m, b): i for i, (m, b) in enumerate(itertools.product(MODELS, BASES))}
    for r in sorted(mine, key=lambda r: (r["subject"], r["trial"], order.get((r["model"], r["basis"]), 99))):
        best, rej = r["best"], r["rejection"]
        person = rej.get("person") or {}
        optimum = rej.get("synthetic_projection") or {}
        failed = sum(not d["success"] for d in r["directions"])
        lines.append(
            f"| {r['subject']} | {r['trial']} | {r['model']} | {r['basis']} | {best.get('label') or '-'} | "
            f"{_num(best['rmse_deg'])} | {_num(best['step_length'], '.3f')} / {_num(r['person_step_length'], '.3f')} | "
            f"{_num(best['step_length_error'], '.3f')} | {_num(r['projection']['rmse_deg'])} | "
            f"{_num(person.get('relative_residual'), '.3g')} / {_num(optimum.get('relative_residual'), '.3g')} | "
            f"{rej['verdict']} | {failed} / {r['n_directions']} | {r['solves']} | {r['wall_time']:.0f} |"
        )
    paired = paired_table(mine)
    return "\n".join([*lines, *([""] if paired else []), *paired])


def effort_floor_of_rich(record: dict[str, Any]) -> tuple[float | None, str | None]:
    """The best RMSE (and its direction) over a rich unit's directions that weigh the model's
    efforts only: the effort cell's problems, solved inside the rich basis from the same
    starts. On the walker's 12 trials this equals the effort unit's own floor within 0.001
    deg (single directions may differ where their optimum is not unique)."""
    effort = set(basis_features(record["model"], "effort"))
    best: tuple[float | None, str | None] = (None, None)
    for d in record["directions"]:
        rmse = d.get("rmse_deg")
        weighs_others = any(k and f not in effort for f, k in zip(record["features"], d["lattice"]))
        if d["success"] and rmse is not None and not weighs_others and (best[0] is None or rmse < best[0]):
            best = (rmse, d["label"])
    return best


def paired_table(records: Sequence[dict[str, Any]]) -> list[str]:
    """Per trial with a rich unit, each model's floors side by side: the effort unit's, the
    rich unit's over its effort directions (:func:`effort_floor_of_rich`) and the rich unit's;
    then their medians over the trials every model's rich unit ran, so the cells compare on
    the same trials."""
    units = {(r["subject"], r["trial"], r["model"], r["basis"]): r for r in records}
    trials = sorted({(s, t) for s, t, _, b in units if b == "rich"})
    if not trials:
        return []
    lines = [
        "Floors per trial (best leg-angle RMSE, deg): the effort unit's, the rich unit's over its effort "
        "directions only, and the rich unit's (- where a unit did not run):",
        "",
        "| subject | trial | model | effort unit | rich unit, effort directions | rich unit |",
        "|---|---|---|---|---|---|",
    ]
    cells: dict[tuple[str, str], dict[tuple[str, str], float | None]] = {}
    for s, t in trials:
        for m in MODELS:
            rich, effort = units.get((s, t, m, "rich")), units.get((s, t, m, "effort"))
            if rich is None and effort is None:
                continue
            own = effort["best"]["rmse_deg"] if effort else None
            inner = effort_floor_of_rich(rich)[0] if rich else None
            whole = rich["best"]["rmse_deg"] if rich else None
            lines.append(f"| {s} | {t} | {m} | {_num(own)} | {_num(inner)} | {_num(whole)} |")
            if rich is not None:
                cells.setdefault((s, t), {})[m, "effort"] = own if own is not None else inner
                cells[s, t][m, "rich"] = whole
    both = [k for k, v in cells.items() if all((m, "rich") in v for m in MODELS)]
    if both:
        medians = {c: _median(cells[k][c] for k in both) for c in itertools.product(MODELS, BASES)}
        lines += [
            "",
            f"Medians over the {len(both)} trial(s) where every model's rich unit ran "
            f"({', '.join(f'{s} {t}' for s, t in both)}); effort: the effort unit's floor, or the rich unit's "
            "over its effort directions where no effort unit ran:",
            "",
            "| model | " + " | ".join(BASES) + " |",
            "|---|" + "---|" * len(BASES),
            *(f"| {m} | " + " | ".join(_num(medians[m, b]) for b in BASES) + " |" for m in MODELS),
        ]
    return lines


# -- measuring (solves) --------------------------------------------------------------------------------
def _feet_floor():
    """``studies/feet_floor.py`` (its projection: start, tracking, foot angles), loaded by path."""
    if "feet_floor" not in sys.modules:
        spec = importlib.util.spec_from_file_location("feet_floor", Path(__file__).with_name("feet_floor.py"))
        module = importlib.util.module_from_spec(spec)
        sys.modules["feet_floor"] = module
        spec.loader.exec_module(module)
    return sys.modules["feet_floor"]


_ANKLE_MODELS: dict[str, GaitModel] = {}


def study_model(label: str, step) -> tuple[GaitModel, Any]:
    """The cell's model and the subject's parameters on it (one ankle model per distinct
    parameters, so a subject's trials share its built problems)."""
    if label == "walker":
        return WALKER, step.params
    b = step.body.lengths
    params = footed_params(b.thigh, b.shank, b.ankle_height, b.foot, step.body.height, "ankle", "free")
    key = json.dumps(params.to_dict(), sort_keys=True)
    if key not in _ANKLE_MODELS:
        _ANKLE_MODELS[key] = footed_model("study-ankle", params)
    return _ANKLE_MODELS[key], params


def _rmse(trajectory, model, person_angles) -> float:
    from ioc_bench.human.observe import leg_angles
    from ioc_bench.human.scoring import rmse_deg

    return rmse_deg(leg_angles(trajectory, model), person_angles)


def _segment_angles(trajectory, forward, names: Sequence[str]) -> dict[str, np.ndarray]:
    segments = forward.step.seg_names
    return {n: trajectory.q[:, segments.index(n), 2] for n in names if n in segments}


def project(forward, model, params, targets: dict[str, np.ndarray], task: Task, dt: float):
    """The model's step closest to ``targets`` (segment -> angles) at ``task`` with a
    vanishing effort (``feet_floor.py``'s projection), from the angles placed as a start;
    tried again from the rough guess of the task's step length if that fails. ``forward``
    weighs the effort basis. Returns (result, solves)."""
    from ioc_bench.trajopt.forward_problem import SolveRequest
    from ioc_bench.trajopt.initial_guess import rough_step
    from ioc_bench.trajopt.solution import StartPoint

    ff = _feet_floor()
    n_knots = forward.n_knots
    nominal = np.ones(len(forward.features)) / math.sqrt(len(forward.features))
    shape = SimpleNamespace(n_knots=n_knots, dt=dt)  # what human_start reads of a step
    start = ff.human_start(forward, model, params, shape, targets)
    request = SolveRequest(
        StartPoint(start), params, task, nominal * ff.PROJECTION_EFFORT, ff.tracking(forward, targets)
    )
    result = forward.solve(request)
    if result.report.success:
        return result, 1
    guess = forward.step.layout.pack(rough_step(model, params, task.speed, n_knots, GuessShape(step=task.step_length)))
    again = forward.solve(SolveRequest(StartPoint(guess), params, task, request.weights, request.tracking))
    return (again if again.report.success else result), 2


def kkt_test(forward, params, speed: float, x: np.ndarray) -> dict[str, Any]:
    """The inverse-KKT fit at ``x`` of ``forward``'s basis at the speed-only task."""
    from ioc_bench.ioc.forward_view import ForwardView
    from ioc_bench.ioc.inverse_kkt import InverseKKTConfig, fit_kkt
    from ioc_bench.ioc.oracle import OracleStats

    # The view's observation and spans serve its tracking methods only, which the fit does not call.
    view = ForwardView(forward, forward.features, params, Task(speed), None, None, OracleStats())
    try:
        fit = fit_kkt(view, x, InverseKKTConfig())
    except (RuntimeError, ValueError, np.linalg.LinAlgError) as exc:
        return {"error": f"{type(exc).__name__}: {exc}", "relative_residual": None}
    return {
        "relative_residual": fit.relative_residual,
        "residual": fit.residual,
        "success": fit.success,
        "weights": dict(zip(forward.features, fit.weights)),
        "penalty": fit.penalty,
        "active_constraints": int(fit.active.g_lower.sum() + fit.active.g_upper.sum()),
        "active_bounds": int(fit.active.x_lower.sum() + fit.active.x_upper.sum()),
    }


def solve_direction(forward, model, params, task: Task, weights: np.ndarray, starts) -> tuple[Any, dict[str, Any]]:
    """Every start for ``weights``; the kept optimum (cheapest feasible) and its summary."""
    from ioc_bench.trajopt.forward_problem import SolveRequest
    from ioc_bench.trajopt.multistart import pick_best
    from ioc_bench.trajopt.solution import StartPoint

    origins, points = starts
    results = [forward.solve(SolveRequest(StartPoint(x0), params, task, weights)) for x0 in points]
    best, summary = pick_best(results, origins)
    return results[best], {
        "best_start": best,
        "feasible_starts": len(summary.feasible),
        "distinct_optima": len(summary.optima),
        "solves": len(results),
        "iterations": sum(r.report.iterations for r in results),
        "wall_time": sum(r.report.wall_time for r in results),
    }


def measure_unit(ctx, model_label: str, basis: str, projection, args, log) -> dict[str, Any]:
    """One (subject, trial, model, basis): every direction, the floor and the rejection test."""
    from ioc_bench.human.baselines import log_error
    from ioc_bench.trajopt.forward_problem import get_forward_problem
    from ioc_bench.trajopt.initial_guess import multistart_guesses

    t0 = time.perf_counter()
    step = ctx.step
    model, params = study_model(model_label, step)
    n_intervals = (step.n_knots - 1) // 2
    features = basis_features(model_label, basis)
    forward = get_forward_problem(model, n_intervals, features)
    speed, person_length = step.task.speed, step.task.step_length
    task = Task(speed)
    tried = multistart_guesses(model, params, speed, None, forward.n_knots, args.starts, args.seed)
    starts = ([o for o, _ in tried], [forward.step.layout.pack(b) for _, b in tried])
    directions, kept = [], []
    for point in lattice(len(features), args.divisions):
        w = np.asarray(point, dtype=float)
        w /= np.linalg.norm(w)
        result, summary = solve_direction(forward, model, params, task, w, starts)
        ok = result.report.success
        length = result.trajectory.duration * speed if ok else float("nan")
        phi = forward.step.features_fn(result.x, forward.parameters(params, task, w)) if ok else None
        d = {
            "lattice": list(point),
            "label": direction_label(features, point),
            "weights": w,
            "success": ok,
            "status": result.report.status,
            "objective": result.report.objective,
            "rmse_deg": _rmse(result.trajectory, model, step.angles) if ok else None,
            "step_length": length,
            "step_length_error": log_error(length, person_length),
            "features": None if phi is None else dict(zip(features, np.asarray(phi, dtype=float).ravel())),
            **summary,
        }
        directions.append(d)
        kept.append(result)
        if args.verbose:
            print(
                f"    {d['label']}: {_num(d['rmse_deg'])} deg, step {_num(length, '.3f')} L, {d['status']}, "
                f"{d['feasible_starts']}/{d['solves']} feasible, {d['wall_time']:.0f} s",
                file=log,
                flush=True,
            )
    fits = [(d["rmse_deg"], i) for i, d in enumerate(directions) if d["success"] and d["rmse_deg"] is not None]
    best_i = min(fits)[1] if fits else None
    best = dict(directions[best_i]) if best_i is not None else {"rmse_deg": None, "step_length": None}
    best.setdefault("step_length_error", None)
    if best_i is not None:
        best["index"] = best_i
        best["angles"] = np.round(
            kept[best_i].trajectory.q[:, [forward.step.seg_names.index(s) for s in LEG_SEGMENTS], 2], 6
        )

    proj_result, proj_solves = projection
    rejection: dict[str, Any] = {"factor": REJECT_FACTOR, "synthetic_projection": None, "optimum": None}
    rejection["person"] = kkt_test(forward, params, speed, proj_result.x) if proj_result.report.success else None
    solves = sum(d["solves"] for d in directions)  # and the synthetic projection's (the person's: its own record)
    if best_i is not None:
        optimum = kept[best_i]
        at_optimum = kkt_test(forward, params, speed, optimum.x)
        if at_optimum.get("weights") is not None:
            recovered = np.array([at_optimum["weights"][f] for f in features])
            at_optimum["weight_error"] = float(np.linalg.norm(recovered - directions[best_i]["weights"]))
        rejection["optimum"] = at_optimum
        effort = get_forward_problem(model, n_intervals, basis_features(model_label, "effort"))
        targets = _segment_angles(optimum.trajectory, effort, LEG_SEGMENTS + FEET)
        targets = {n: a for n, a in targets.items() if np.ptp(a) > 1e-9}  # tracking divides by each span
        synthetic, n = project(
            effort, model, params, targets, Task(speed, directions[best_i]["step_length"]), optimum.trajectory.dt
        )
        solves += n
        rejection["synthetic_projection"] = {
            "projection_ok": synthetic.report.success,
            "projection_status": synthetic.report.status,
            "rmse_to_optimum_deg": _rmse(synthetic.trajectory, model, best["angles"]),
        }
        if synthetic.report.success:
            rejection["synthetic_projection"] |= kkt_test(forward, params, speed, synthetic.x)
    person_rr, synthetic_rr = (_fitted(rejection[k]) for k in ("person", "synthetic_projection"))
    rejection["ratio"] = person_rr / synthetic_rr if person_rr is not None and synthetic_rr else None
    rejection["verdict"] = verdict(person_rr, synthetic_rr)
    return {
        "subject": ctx.subject,
        "trial": ctx.trial_code,
        "model": model_label,
        "basis": basis,
        "features": list(features),
        "divisions": args.divisions,
        "starts": args.starts,
        "seed": args.seed,
        "n_knots": step.n_knots,
        "speed": speed,
        "person_step_length": person_length,
        "n_directions": len(directions),
        "directions": directions,
        "best": best,
        "projection": {
            "ok": proj_result.report.success,
            "status": proj_result.report.status,
            "solves": proj_solves,
            "wall_time": proj_result.report.wall_time,
            "rmse_deg": _rmse(proj_result.trajectory, model, step.angles),
            "step_length": proj_result.trajectory.duration * speed,
            "angles": np.round(
                proj_result.trajectory.q[:, [forward.step.seg_names.index(s) for s in LEG_SEGMENTS], 2], 6
            ),
        },
        "rejection": rejection,
        "solves": solves,
        "wall_time": time.perf_counter() - t0,
        "finished": time.strftime("%Y-%m-%dT%H:%M:%S"),
    }


def _fitted(test: dict[str, Any] | None) -> float | None:
    """The relative residual of a KKT test whose fit succeeded, else None."""
    return test["relative_residual"] if test and test.get("success") else None


def person_projection(ctx, model_label: str):
    """The person's projection on the model at the trial's task (effort basis)."""
    from ioc_bench.trajopt.forward_problem import get_forward_problem

    ff = _feet_floor()
    step = ctx.step
    model, params = study_model(model_label, step)
    forward = get_forward_problem(model, (step.n_knots - 1) // 2, basis_features(model_label, "effort"))
    targets = ff.target_angles(model, step, ff.foot_angles(step, ctx.trial))
    return project(forward, model, params, targets, step.task, step.dt)


# -- the command line ------------------------------------------------------------------------------------
def _choice(text: str, valid: Sequence[str], what: str, parser: argparse.ArgumentParser) -> tuple[str, ...]:
    chosen = tuple(t.strip() for t in text.split(",") if t.strip())
    bad = [c for c in chosen if c not in valid]
    if bad or not chosen:
        parser.error(f"--{what}: {', '.join(bad) or 'none given'}; valid: {', '.join(valid)}")
    return chosen


def parse_args(argv: Sequence[str] | None = None) -> argparse.Namespace:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--out", type=Path, default=DEFAULT_OUT, help=f"JSON lines file (default {DEFAULT_OUT})")
    ap.add_argument("--subjects", default=",".join(SUBJECTS), help="comma-separated (default: all three)")
    ap.add_argument("--trials", default=",".join(TRIALS), help="comma-separated speed codes (default: T03-T06)")
    ap.add_argument("--models", default=",".join(MODELS), help="walker, ankle (default both)")
    ap.add_argument("--bases", default=",".join(BASES), help="effort, rich (default both)")
    ap.add_argument("--divisions", type=int, default=2, help="simplex lattice divisions (default 2)")
    ap.add_argument("--starts", type=int, default=8, help="seeded starts per direction (default 8)")
    ap.add_argument("--seed", type=int, default=0, help="the starts' seed (default 0)")
    ap.add_argument("--plan", action="store_true", help="list the units left, their solves and time estimate")
    ap.add_argument("--table", action="store_true", help="only print the summary of --out")
    ap.add_argument("-v", "--verbose", action="store_true", help="a line per direction too")
    args = ap.parse_args(argv)
    args.subjects = _choice(args.subjects, SUBJECTS, "subjects", ap)
    args.trials = _choice(args.trials, TRIALS, "trials", ap)
    args.models = _choice(args.models, MODELS, "models", ap)
    args.bases = _choice(args.bases, BASES, "bases", ap)
    if args.divisions < 1 or args.starts < 1 or args.seed < 0:
        ap.error("--divisions and --starts must be >= 1, --seed >= 0")
    return args


def pending(args, records: Sequence[dict[str, Any]]) -> list[tuple[str, str, str, str]]:
    """The chosen (subject, trial, model, basis) units not yet in ``records``, in run order."""
    done = {unit_key(r) for r in records}
    return [
        (s, t, m, b)
        for s in args.subjects
        for t in args.trials
        for m in args.models
        for b in args.bases
        if (s, t, m, b, args.divisions, args.starts, args.seed) not in done
    ]


def plan(args, units: Sequence[tuple[str, str, str, str]]) -> str:
    """What is left: per cell, units, solves and the time estimate on one core."""
    lines = ["| model | basis | directions | units left | solves | estimate on 1 core |", "|---|---|---|---|---|---|"]
    total = [0, 0.0, 0.0]
    for m in MODELS:
        for b in BASES:
            n = sum(1 for u in units if u[2:] == (m, b))
            if not n:
                continue
            solves = n * unit_solves(m, b, args.divisions, args.starts)
            builds = len({u[0] for u in units if u[2:] == (m, b)}) * 2 * SECONDS_PER_BUILD[m]
            lo, hi = (solves * s + builds for s in SECONDS_PER_SOLVE[m])
            total = [total[0] + solves, total[1] + lo, total[2] + hi]
            dirs = lattice_size(len(basis_features(m, b)), args.divisions)
            lines.append(f"| {m} | {b} | {dirs} | {n} | {solves} | {lo / 60:.0f}-{hi / 60:.0f} min |")
    lines.append(f"| all | | | {len(units)} | {total[0]} | {total[1] / 3600:.1f}-{total[2] / 3600:.1f} h |")
    return "\n".join(lines) + "\n(an estimate from SECONDS_PER_SOLVE, not a measurement)"


def main(argv: Sequence[str] | None = None) -> None:
    args = parse_args(argv)
    records = read_records(args.out)
    if args.table:
        print(table(records, args.divisions, args.starts, args.seed))
        return
    units = pending(args, records)
    if args.plan:
        print(plan(args, units))
        return
    if not units:
        print("nothing left to measure for these choices", file=sys.stderr)
        print(table(read_records(args.out), args.divisions, args.starts, args.seed))
        return
    from ioc_bench.human import WbdsData, human_step

    args.out.parent.mkdir(parents=True, exist_ok=True)
    data = WbdsData()
    log, done = sys.stderr, 0
    for (subject, code), group in itertools.groupby(units, key=lambda u: u[:2]):
        trial = data.trial(subject, code)
        ctx = SimpleNamespace(subject=subject, trial_code=code, trial=trial, step=human_step(trial))
        group = list(group)
        for model_label in dict.fromkeys(u[2] for u in group):
            projection = person_projection(ctx, model_label)
            for *_, basis in (u for u in group if u[2] == model_label):
                record = measure_unit(ctx, model_label, basis, projection, args, log)
                append_record(args.out, record)
                done += 1
                print(f"[{done}/{len(units)}] {_progress(record)}", file=log, flush=True)
    print(table(read_records(args.out), args.divisions, args.starts, args.seed))


def _progress(r: dict[str, Any]) -> str:
    best, rej = r["best"], r["rejection"]
    person = (rej.get("person") or {}).get("relative_residual")
    synthetic = (rej.get("synthetic_projection") or {}).get("relative_residual")
    failed = sum(not d["success"] for d in r["directions"])
    return (
        f"{r['subject']} {r['trial']} {r['model']} {r['basis']}: best {_num(best['rmse_deg'])} deg at "
        f"{best.get('label') or '-'}, step {_num(best['step_length'], '.3f')} vs {r['person_step_length']:.3f} L; "
        f"projection {_num(r['projection']['rmse_deg'])} deg; KKT {_num(person, '.3g')} vs {_num(synthetic, '.3g')} "
        f"-> {rej['verdict']}; {failed}/{r['n_directions']} directions failed; {r['solves']} solves, "
        f"{r['wall_time']:.0f} s"
    )


if __name__ == "__main__":
    main()
