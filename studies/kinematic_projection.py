"""Why the `noise-kinematics` condition is hard: the projected observation's features.

Without measured torques, the IOC's feasible projection of a step observed with 5 % noise
on positions and velocities tracks that noise with the walker's dynamics, which takes large
and fast-changing torques. This prints the projection's features beside the
demonstration's for three ways of building it: the plain projection (what `IOCProblem.reference`
returns), the projection of a Savitzky-Golay-smoothed observation (what a lab's filter
would do), and the projection with an added effort term under uniform weights (a
regularised projection, biased toward those weights). It also prints each projection's
tracking error beside the true step's: a projection below the truth's error has fitted noise.

    python studies/kinematic_projection.py          # ~2 minutes on one core
"""

from __future__ import annotations

import dataclasses

import numpy as np
from scipy.signal import savgol_filter

from ioc_bench.features import COST_FEATURES, evaluate
from ioc_bench.ioc.problem import PROJECTION_SCALE, IOCProblem
from ioc_bench.model.params import WalkerParams
from ioc_bench.synthetic.case import NOISE_STREAM
from ioc_bench.synthetic.conditions import get_condition
from ioc_bench.synthetic.demos import demonstration
from ioc_bench.synthetic.observe import observe
from ioc_bench.task import Task
from ioc_bench.trajopt.forward_problem import SolveRequest, get_forward_problem
from ioc_bench.trajopt.solution import StartPoint
from ioc_bench.trajopt.tracking import signal_spans, tracking_terms
from ioc_bench.weights import parse_weights


def row(name: str, trajectory, problem: IOCProblem, truth) -> str:
    phi = evaluate(trajectory, problem.params, COST_FEATURES)
    feats = " / ".join(f"{phi[f]:.3g}" for f in COST_FEATURES)
    return f"| {name} | {feats} | {problem.tracking_error(trajectory):.5f} | {problem.tracking_error(truth):.5f} |"


def main() -> None:
    cond, params, solver = get_condition("noise-kinematics"), WalkerParams(), get_forward_problem()
    print("| projection | hip / knee / dtau | tracking error | true step's tracking error |")
    print("|---|---|---|---|")
    for name in ("nominal", "penalize-knee"):
        demo = demonstration(parse_weights(name), task=Task(0.27), seed=0)
        obs = observe(demo.trajectory, cond.noise, np.random.default_rng([0, NOISE_STREAM]), cond.torques)
        problem = IOCProblem(obs, cond.features, params, cond.ioc_task(), seed=0)
        phi = " / ".join(f"{demo.features[f]:.3g}" for f in COST_FEATURES)
        print(f"| **{name}, seed 0: the demonstration** | {phi} | | |")
        print(row("plain (`reference()`)", problem.reference().trajectory, problem, demo.trajectory))
        for window in (5, 9, 13):
            smooth = dataclasses.replace(
                obs,
                q=savgol_filter(obs.q, window, 3, axis=0, mode="interp"),
                v=savgol_filter(obs.v, window, 3, axis=0, mode="interp"),
            )
            print(row(f"Savitzky-Golay {window} knots", problem.project(smooth).trajectory, problem, demo.trajectory))
        tracking = tracking_terms(obs, PROJECTION_SCALE, signal_spans(obs, len(solver.actuators)))
        start = StartPoint(solver.guess_vector(obs, params))
        for mu in (1e-3, 1e-2, 1e-1):
            w = np.zeros(len(solver.features))
            w[: len(COST_FEATURES)] = mu / np.sqrt(len(COST_FEATURES))
            result = solver.solve(SolveRequest(start, params, problem.task, w, tracking))
            label = f"plus uniform effort x {mu:g}" + ("" if result.report.success else " (failed)")
            print(row(label, result.trajectory, problem, demo.trajectory))


if __name__ == "__main__":
    main()
