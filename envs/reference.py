"""A demonstration as a reference to track or check: times, joint paths, torques, and its phase.

The optimizer stores a step as segment states at Hermite-Simpson knots, legs named by role
(stance, swing). The tracking policy and the replay checks need it as MuJoCo coordinates,
as actuated joint angles at any time, and as a function of the step's **phase**: the hip's
forward distance from the stance foot, which grows steadily through every demonstrated
step. Nothing here assumes a step length or duration; everything is read off the
demonstration.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from envs.coordinates import check_actuators, to_generalized
from ioc_bench.demo import Demonstration
from ioc_bench.model.catalogue import get_model
from ioc_bench.model.linkage import Linkage, point_offset
from ioc_bench.model.mjcf import check_mjcf_model
from ioc_bench.model.walker import ACTUATORS
from ioc_bench.trajopt.collocation import interpolate, quadratic

#: Fine samples of the phase path per knot interval (enough for linear interpolation).
PHASE_SAMPLES_PER_KNOT = 20


@dataclass(frozen=True, eq=False)
class DemoReference:
    """A demonstration in the form the tracking policy and the replays use: the reference
    they track or check against (:meth:`of` builds it).

    Attributes:
        linkage: the demonstration's linkage.
        times: (T,) knot times.
        theta: (T, 2S) segment angles and angular velocities (the collocated state).
        dtheta: (T, 2S) their time derivatives.
        tau: (T, 4) actuated torques in ``ACTUATORS`` (role) order.
        joint_map: (4, S) actuated joint angles = ``joint_map @ segment angles``.
        qpos, qvel, qacc: (T, 7) MuJoCo coordinates of every knot, leg ``a`` in stance.
    """

    linkage: Linkage
    times: np.ndarray
    theta: np.ndarray
    dtheta: np.ndarray
    tau: np.ndarray
    joint_map: np.ndarray
    qpos: np.ndarray
    qvel: np.ndarray
    qacc: np.ndarray

    @classmethod
    def of(cls, demo: Demonstration) -> DemoReference:
        link = demo_linkage(demo)
        tr = demo.trajectory
        jmap = np.zeros((len(ACTUATORS), len(link.segments)))
        for i, joint in enumerate(link.actuated):
            jmap[i, link.index(joint.child)] += 1.0
            jmap[i, link.index(joint.parent)] -= 1.0
        knots = [to_generalized(link, tr.q[k], tr.v[k], tr.acc[k], "a") for k in range(tr.n_knots)]
        qpos, qvel, qacc = (np.array([kn[i] for kn in knots]) for i in range(3))
        return cls(
            linkage=link,
            times=tr.times,
            theta=np.concatenate([tr.q[:, :, 2], tr.v[:, :, 2]], axis=1),
            dtheta=np.concatenate([tr.v[:, :, 2], tr.acc[:, :, 2]], axis=1),
            tau=tr.tau,
            joint_map=jmap,
            qpos=qpos,
            qvel=qvel,
            qacc=qacc,
        )

    @property
    def duration(self) -> float:
        return float(self.times[-1])

    @property
    def dt(self) -> float:
        """Time between knots."""
        return float(self.times[1] - self.times[0])

    def joints(self, t: float) -> tuple[np.ndarray, np.ndarray]:
        """Actuated joint angles and rates (``ACTUATORS`` order) at time ``t``."""
        state, _ = interpolate(self.times, self.theta, self.dtheta, t)
        n = self.joint_map.shape[1]
        return self.joint_map @ state[:n], self.joint_map @ state[n:]

    def torque(self, t: float) -> np.ndarray:
        """Feed-forward torques (``ACTUATORS`` order) at time ``t``, quadratic per interval."""
        return quadratic(self.times, self.tau, t)

    def phase_path(self, per_knot: int = PHASE_SAMPLES_PER_KNOT) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Fine samples ``(t, x, xdot)`` of the hip's forward distance from the stance foot.

        Raises:
            ValueError: if the distance does not grow strictly through the step (the phase
                would then not identify a time).
        """
        tg = np.linspace(0.0, self.duration, per_knot * (len(self.times) - 1) + 1)
        n = self.joint_map.shape[1]
        rows = []
        for t in tg:
            state, _ = interpolate(self.times, self.theta, self.dtheta, t)
            rows.append(hip_over_foot(self.linkage, state[:n], state[n:]))
        x, xd = np.array(rows).T
        if np.any(np.diff(x) <= 0):
            raise ValueError("the demonstration's hip does not move steadily forward over the stance foot")
        return tg, x, xd


def demo_linkage(demo: Demonstration) -> Linkage:
    """The linkage of ``demo``'s gait model and parameters (``ValueError`` if its model has no
    MuJoCo model, or its actuators are not the MuJoCo models')."""
    return check_actuators(get_model(check_mjcf_model(demo.model)).linkage(demo.params))


def hip_over_foot(link: Linkage, theta: np.ndarray, omega: np.ndarray) -> tuple[float, float]:
    """Forward position and velocity of the hip relative to the stance foot, from segment angles.

    The stance foot is where the ground pin holds it: the foot point, or for a rolling arc
    its anchor (``R theta`` behind the arc's centre, the contact point), which stays put
    while the arc rolls. So the velocity is the hip's own while the foot does not slip.

    Args:
        link: the walker's linkage (role-named segments).
        theta, omega: (S,) segment angles and angular velocities, linkage storage order.
    """
    x = xd = 0.0
    for name, (upper, lower) in (("thigh_stance", ("hip", "knee")), ("shank_stance", ("knee", "foot"))):
        i = link.index(name)
        segment = link.segments[i]
        (ux, uz), (lx, lz) = (point_offset(segment, p, theta[i]) for p in (upper, lower))
        x += float(ux - lx)
        xd += float(omega[i] * (uz - lz))
        if lower in segment.rolls:
            x += float(segment.rolls[lower] * theta[i])
            xd += float(segment.rolls[lower] * omega[i])
    return x, xd
