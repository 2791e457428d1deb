"""The cutting-plane loop's stop rules and cut rules, on a stub problem (no solver)."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np

from ioc_bench.ioc.cutting_plane import CuttingPlane, LogBarrierStep, PlainForward, ReferenceChoice, min_error_output

PHI_REF = np.array([1.0, 2.0, 3.0])


class StubProblem:
    """Features of x* are PHI_REF; optimize() returns the scripted feature vectors in turn."""

    n_features = 3
    seed = 0

    def __init__(self, steps):
        self.steps = list(steps)
        self.observed = SimpleNamespace(tau=np.zeros((3, 4)))

    @property
    def trials(self):
        return (self,)

    def reference(self):
        return SimpleNamespace(success=True, trajectory="x-hat")

    def features_of(self, step):
        return PHI_REF.copy()

    def rng(self, stream=0):
        return np.random.default_rng(stream)

    def optimize(self, w, start=None, starts=1, **_):
        phi = self.steps.pop(0)
        ok = phi is not None
        return SimpleNamespace(success=ok, status="ok" if ok else "Infeasible", features=phi, trajectory="step")

    def tracking_error(self, step):
        return 1.0

    def trajectory_error(self, step):
        return 1.0


def _loop(**kw):
    base = dict(
        reference=ReferenceChoice("observed"),
        weight_step=LogBarrierStep(),
        forward=PlainForward("warm", 1),
        output=min_error_output,
        n_random=0,
        perturbation=0.05,
        max_iterations=5,
        weight_tol=1e-12,
        cut_threshold=1e-6,
        stop_without_cut=False,
    )
    return CuttingPlane(**(base | kw))


def test_a_failed_forward_solve_stops_the_run_and_says_so():
    result = _loop().run(StubProblem([PHI_REF * 1.1, None]))
    assert result.status == "forward_failed"  # not "converged" on repeated weights
    assert len(result.history) == 2 and result.history[-1].solve_status == "Infeasible"


def test_a_step_equal_to_the_reference_is_not_a_cut():
    problem = StubProblem([PHI_REF * np.array([1.2, 1.0, 1.0]), PHI_REF * (1 + 1e-9)])
    result = _loop(max_iterations=2).run(problem)
    assert len(result.history) == 2
    assert result.notes["cuts"] == 1  # the second step is x* again, to 1e-9: no cut
