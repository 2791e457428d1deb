"""What the IOC observes: only what a lab measures, noise on what is measured."""

from __future__ import annotations

import numpy as np

from ioc_bench.synthetic.observe import observe
from ioc_bench.trajectory import Observation, Trajectory
from ioc_bench.trajopt.tracking import signal_spans


def test_exact_observation_drops_what_a_lab_cannot_measure(nominal_demo):
    seen = observe(nominal_demo.trajectory, 0.0, np.random.default_rng(0))
    assert type(seen) is Observation and not isinstance(seen, Trajectory)
    assert np.array_equal(seen.q, nominal_demo.trajectory.q) and np.array_equal(seen.tau, nominal_demo.trajectory.tau)


def test_noise_is_applied_to_what_is_measured(nominal_demo):
    traj = nominal_demo.trajectory
    seen = observe(traj, 0.05, np.random.default_rng(0))
    spans = signal_spans(traj.observed())
    z = (seen.signals() - traj.signals()) / spans
    assert 0.045 < z.std() < 0.055 and abs(z.mean()) < 0.005  # sigma 5 % of each signal's span
    kinematic = observe(traj, 0.05, np.random.default_rng(0), torques=False)
    assert kinematic.tau is None  # torques not measured: not observed at all
    assert np.isnan(kinematic.signals(4)[:, -4:]).all()
