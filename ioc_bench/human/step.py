"""One symmetric human step in the walker's coordinates and units.

The walker's step runs from heel strike of the stance leg (knot 0) to heel strike of the
swing leg (the last knot), after which the legs swap roles. A WBDS trial gives the mean
stride of each leg, each normalised to its own stride (0 % and 100 % at its heel strikes).
The mapping:

1. **Segment angles.** Per side, the thigh's angle from vertical (flexion positive) is hip
   flexion minus anterior pelvic tilt, and the shank's is that minus knee flexion (the Z
   columns of ``*ang.txt``). In the walker's convention an angle is that of the segment's
   axis from its distal to its proximal end, positive when the proximal end is ahead
   (:mod:`ioc_bench.model.linkage`), so the walker's angle is minus the flexion angle: the
   stance leg starts at a negative angle, the foot ahead of the hip.
2. **One symmetric leg.** Right and left strides are averaged sample by sample (both legs
   of the mean cycle), then made periodic (the 0 % and 100 % samples averaged) and
   interpolated by periodic cubic splines over the stride phase.
3. **One step.** Contralateral heel strike is taken at 50 % of the stride (a symmetric
   step; the mean-cycle files carry no event times). At the step's fraction s in [0, 1],
   the stance leg is at stride phase s/2 and the swing leg at 1/2 + s/2.
4. **Time.** The step lasts step length / speed (the laboratory's table; the mean-cycle
   files carry no stride time), expressed in the walker's time unit sqrt(L/g), with L
   the subject's leg length from the standing trial and g = 9.81; the knots are the
   walker's (41 knots for 20 Hermite-Simpson intervals). Rates are the splines'
   derivatives.
5. **Task.** Speed in sqrt(g L), step length in L, both from the table (or, as a stated
   choice, the step length of the subject's trend over its other speeds).
6. **Moments** (a stated variant). Hip moments are flexor-positive and knee moments
   extensor-positive in the files (checked by the signs of joint power: positive hip power
   at loading, negative knee power in terminal swing); the walker's hip torque is extensor-
   positive and its knee torque flexor-positive, so both change sign, and N m/kg becomes
   m g L by dividing by g L.
7. **Ground forces.** N/kg divided by the measured weight per kg: the stride mean of both
   feet's vertical force (the treadmill carries the whole weight on average), not g times
   the listed mass (see the data's README: about 94 % of the listed weight for WBDS01).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.interpolate import CubicSpline

from ioc_bench.features import PAPER_GRAVITY
from ioc_bench.human.anthropometry import SubjectBody, subject_body
from ioc_bench.human.wbds import TableRow, WbdsTrial
from ioc_bench.model.params import WalkerParams
from ioc_bench.task import Task
from ioc_bench.trajopt.step_problem import DEFAULT_INTERVALS
from ioc_bench.validation import check_count

#: The walker's leg segments, in the order of a human step's angle arrays.
LEG_SEGMENTS: tuple[str, ...] = ("thigh_stance", "shank_stance", "thigh_swing", "shank_swing")
#: Stride phase of contralateral heel strike (a symmetric step).
CONTRALATERAL_PHASE = 0.5
#: Relative departure of a table step length from the subject's trend that is flagged.
TREND_TOLERANCE = 0.10
#: Vertical force (body weights) above which a foot counts as on the ground.
CONTACT_THRESHOLD = 0.02
#: Stride phase window of the stance knee's loading flexion.
LOADING_WINDOW = (0.0, 0.3)


class LegCycle:
    """One symmetric leg over its stride: periodic splines of every mapped signal.

    Signals, all in the walker's convention and units (angles rad, torques m g L, forces
    body weights): ``thigh``, ``shank`` (segment angles), ``hip``, ``knee`` (torques),
    ``fx``, ``fz`` (ground force on the foot). Phase 0 is heel strike.
    """

    SIGNALS = ("thigh", "shank", "hip", "knee", "fx", "fz")

    def __init__(self, samples: dict[str, np.ndarray]):
        n = len(next(iter(samples.values())))
        phase = np.linspace(0.0, 1.0, n)
        self._splines = {}
        for name in self.SIGNALS:
            y = np.array(samples[name], dtype=float)
            y[0] = y[-1] = 0.5 * (y[0] + y[-1])
            self._splines[name] = CubicSpline(phase, y, bc_type="periodic")

    def __call__(self, name: str, phase: np.ndarray, derivative: int = 0) -> np.ndarray:
        """Signal ``name`` (or its ``derivative``-th derivative in phase) at stride ``phase``."""
        return self._splines[name](np.mod(phase, 1.0), derivative)


@dataclass(frozen=True, eq=False)
class GroundForces:
    """Ground reaction forces of a human step, body weights, walker axes (x forward, z up).

    Attributes:
        stance: (T, 2) on the stance foot.
        swing: (T, 2) on the other foot: the trailing foot early in the step (double
            support), the landing foot at its end; zero in between.
    """

    stance: np.ndarray
    swing: np.ndarray

    @property
    def total(self) -> np.ndarray:
        """(T, 2) both feet together: what the walker's single stance foot must supply."""
        return self.stance + self.swing


@dataclass(frozen=True)
class StepChecks:
    """What the mapping measured about a trial and its fit to the walker.

    Attributes:
        asymmetry_deg: RMS over the stride of the right-left difference of the thigh and
            shank angles, deg (what averaging the legs removes).
        stance_knee_flexion_deg: peak knee flexion at loading (0-30 % of the stride), deg;
            the walker's stance knee stays locked at 0.
        min_knee_flexion_deg: least knee flexion over the stride (negative: hyperextension,
            which the walker's knee-lock forbids).
        stance_fraction: share of the stride with the foot on the ground (vertical force
            above 2 % body weight, smoothed mean-cycle forces).
        double_support_step: share of a step with both feet on the ground,
            ``2 * (stance_fraction - 1/2)``; the walker has none.
        weight_ratio: measured weight (stride-mean vertical force) over g times the listed mass.
        closure_deg: largest jump between the 0 % and 100 % samples of the angles, deg.
        pose_step_length: distance between the feet at heel strike from the mapped angles
            and the walker's segment lengths, leg lengths (the task's step length is the
            table's).
        trend_step_length: the subject's step length at this speed from a power-law fit of
            step length on speed over its other table rows (None with fewer than 3), leg lengths.
        table_step_length: the table's step length, leg lengths.
    """

    asymmetry_deg: float
    stance_knee_flexion_deg: float
    min_knee_flexion_deg: float
    stance_fraction: float
    double_support_step: float
    weight_ratio: float
    closure_deg: float
    pose_step_length: float
    trend_step_length: float | None
    table_step_length: float

    @property
    def trend_departure(self) -> float | None:
        """Relative departure of the table's step length from the trend (None without one)."""
        if self.trend_step_length is None:
            return None
        return self.table_step_length / self.trend_step_length - 1.0

    def notes(self) -> list[str]:
        """One line per finding a user of this step should know."""
        out = []
        dep = self.trend_departure
        if dep is not None and abs(dep) > TREND_TOLERANCE:
            out.append(
                f"the table's step length {self.table_step_length:.3f} L departs {100 * dep:+.0f} % from the "
                f"subject's trend over its other speeds ({self.trend_step_length:.3f} L)"
            )
        if self.min_knee_flexion_deg < -2.0:
            knee = self.min_knee_flexion_deg
            out.append(f"the knee hyperextends to {knee:.1f} deg (the walker's knee-lock forbids it)")
        return out


@dataclass(frozen=True, eq=False)
class HumanStep:
    """A person's mean step, mapped to the subject's walker (see the module docstring).

    Attributes:
        subject: ``WBDSnn``.
        speed_code: ``T0n``.
        body: the subject's body (leg length, height, mass).
        params: the subject's walker, dimensionless.
        task: the step's speed and length, dimensionless.
        dt: knot spacing, walker time units.
        angles: (T, 4) segment angles of :data:`LEG_SEGMENTS`, rad, walker convention.
        rates: (T, 4) their time derivatives, rad per walker time unit.
        torques: (T, 4) hip and knee moments as walker torques (m g L), in the walker's
            actuator order (hip_stance, hip_swing, knee_stance, knee_swing).
        forces: ground reaction forces, body weights.
        cycle: the symmetric leg's splines (any phase; e.g. for rates of positions).
        checks: what the mapping measured.
    """

    subject: str
    speed_code: str
    body: SubjectBody
    params: WalkerParams
    task: Task
    dt: float
    angles: np.ndarray
    rates: np.ndarray
    torques: np.ndarray
    forces: GroundForces
    cycle: LegCycle
    checks: StepChecks

    @property
    def n_knots(self) -> int:
        return self.angles.shape[0]

    @property
    def duration(self) -> float:
        """Step duration, walker time units."""
        return self.dt * (self.n_knots - 1)

    @property
    def fractions(self) -> np.ndarray:
        """(T,) each knot's fraction of the step, 0..1."""
        return np.linspace(0.0, 1.0, self.n_knots)

    def leg_angles(self, fraction: np.ndarray) -> np.ndarray:
        """(len(fraction), 4) segment angles of :data:`LEG_SEGMENTS` at step fractions."""
        return _leg_signals(self.cycle, np.asarray(fraction, dtype=float), ("thigh", "shank"))


def human_step(
    trial: WbdsTrial,
    n_intervals: int = DEFAULT_INTERVALS,
    step_length: str = "table",
) -> HumanStep:
    """Map one trial to the subject's walker.

    Args:
        trial: a checked WBDS trial (:meth:`ioc_bench.human.wbds.WbdsData.trial`).
        n_intervals: the walker's Hermite-Simpson intervals (knots: 2 n + 1).
        step_length: ``"table"`` (the laboratory's step length) or ``"trend"`` (the subject's
            trend over its other speeds at this speed; for a table row that breaks it).

    Raises:
        ValueError: a bad ``step_length`` or ``n_intervals``, or ``"trend"`` for a subject
            with fewer than three other table rows.
    """
    if step_length not in ("table", "trend"):
        raise ValueError(f"step_length must be 'table' or 'trend', got {step_length!r}")
    n_intervals = check_count(n_intervals, "n_intervals")
    body = subject_body(trial.static, trial.row)
    leg = body.leg_length
    samples, weight = _symmetric_samples(trial, leg)
    cycle = LegCycle(samples)
    trend = _trend_step(trial.row, trial.subject_rows)
    table_step = trial.row.step_length / leg
    if step_length == "trend":
        if trend is None:
            raise ValueError(f"{trial.subject} has too few table rows for a step-length trend")
        step = trend / leg
    else:
        step = table_step
    task = Task(speed=trial.row.speed / body.speed_unit, step_length=step)
    duration = task.step_length / task.speed
    s = np.linspace(0.0, 1.0, 2 * n_intervals + 1)
    stride = duration / CONTRALATERAL_PHASE
    params = body.walker()
    angles = _leg_signals(cycle, s, ("thigh", "shank"))
    rates = _leg_signals(cycle, s, ("thigh", "shank"), derivative=1) / stride
    hips, knees = _leg_signals(cycle, s, ("hip",)), _leg_signals(cycle, s, ("knee",))
    torques = np.column_stack([hips[:, 0], hips[:, 1], knees[:, 0], knees[:, 1]])
    fx, fz = _leg_signals(cycle, s, ("fx",)), _leg_signals(cycle, s, ("fz",))
    forces = GroundForces(np.column_stack([fx[:, 0], fz[:, 0]]), np.column_stack([fx[:, 1], fz[:, 1]]))
    checks = _checks(trial, samples, cycle, weight, params, angles[0], table_step, trend, leg)
    return HumanStep(
        subject=trial.subject,
        speed_code=trial.speed_code,
        body=body,
        params=params,
        task=task,
        dt=duration / (2 * n_intervals),
        angles=angles,
        rates=rates,
        torques=torques,
        forces=forces,
        cycle=cycle,
        checks=checks,
    )


def _leg_signals(cycle: LegCycle, s: np.ndarray, names: tuple[str, ...], derivative: int = 0) -> np.ndarray:
    """(len(s), 2 len(names)): each signal for the stance leg, then for the swing leg."""
    stance = CONTRALATERAL_PHASE * s
    swing = (1.0 - CONTRALATERAL_PHASE) + CONTRALATERAL_PHASE * s
    cols = [cycle(name, phase, derivative) for phase in (stance, swing) for name in names]
    return np.column_stack(cols)


def side_segment_angles(trial: WbdsTrial, side: str) -> tuple[np.ndarray, np.ndarray]:
    """One side's thigh and shank angles over its stride (101 samples), rad, walker convention."""
    a = trial.angles
    thigh_flexion = a[f"{side}HipAngleZ"] - a[f"{side}PelvisAngleZ"]
    shank_flexion = thigh_flexion - a[f"{side}KneeAngleZ"]
    return -np.radians(thigh_flexion), -np.radians(shank_flexion)


def measured_weight(trial: WbdsTrial) -> float:
    """Body weight per kg of listed mass as the force plates saw it (N/kg): the stride mean
    of both feet's vertical force (samples 0..99; 100 repeats 0)."""
    k = trial.kinetics
    return float(k["RGRFY"][:-1].mean() + k["LGRFY"][:-1].mean())


def _symmetric_samples(trial: WbdsTrial, leg: float) -> tuple[dict[str, np.ndarray], float]:
    """The mean of both sides' strides, every signal in walker units, and the measured weight."""
    weight = measured_weight(trial)
    if not weight > 0:
        raise ValueError(f"{trial.kinetics.path.name}: the vertical forces do not carry any weight")
    k = trial.kinetics
    per_side = []
    for side in "RL":
        thigh, shank = side_segment_angles(trial, side)
        per_side.append(
            {
                "thigh": thigh,
                "shank": shank,
                "hip": -k[f"{side}HipMomentZ"] / (PAPER_GRAVITY * leg),
                "knee": -k[f"{side}KneeMomentZ"] / (PAPER_GRAVITY * leg),
                "fx": k[f"{side}GRFX"] / weight,
                "fz": k[f"{side}GRFY"] / weight,
            }
        )
    return {name: 0.5 * (per_side[0][name] + per_side[1][name]) for name in LegCycle.SIGNALS}, weight


def _trend_step(row: TableRow, rows: tuple[TableRow, ...]) -> float | None:
    """Step length (m) at ``row``'s speed from a power law fitted to the subject's other rows."""
    others = [r for r in rows if r.speed_code != row.speed_code]
    if len(others) < 3:
        return None
    slope, offset = np.polyfit(np.log([r.speed for r in others]), np.log([r.step_length for r in others]), 1)
    return float(np.exp(offset + slope * np.log(row.speed)))


def pose_step_length(params: WalkerParams, first_angles: np.ndarray) -> float:
    """Swing foot behind the stance foot at heel strike (knot 0), leg lengths, from the angles.

    A segment of angle theta and length l spans ``l sin(theta)`` forward from its distal to
    its proximal end; the stance foot is ahead of the hip and the swing foot behind.
    """
    th_st, sh_st, th_sw, sh_sw = first_angles
    lt, ls = params.thigh.length, params.shank.length
    hip_from_stance = lt * np.sin(th_st) + ls * np.sin(sh_st)
    hip_from_swing = lt * np.sin(th_sw) + ls * np.sin(sh_sw)
    return float(hip_from_swing - hip_from_stance)


def _checks(trial, samples, cycle, weight, params, first_angles, table_step, trend, leg) -> StepChecks:
    sides = [side_segment_angles(trial, side) for side in "RL"]
    diff = np.degrees(np.concatenate([sides[0][0] - sides[1][0], sides[0][1] - sides[1][1]]))
    knee = np.degrees(samples["shank"] - samples["thigh"])
    lo, hi = LOADING_WINDOW
    loading = knee[round(lo * 100) : round(hi * 100) + 1]
    phase = np.linspace(0.0, 1.0, 1001)[:-1]
    stance = float(np.mean(cycle("fz", phase) > CONTACT_THRESHOLD))
    closure = max(abs(np.degrees(samples[n][-1] - samples[n][0])) for n in ("thigh", "shank"))
    return StepChecks(
        asymmetry_deg=float(np.sqrt(np.mean(diff**2))),
        stance_knee_flexion_deg=float(loading.max()),
        min_knee_flexion_deg=float(knee.min()),
        stance_fraction=stance,
        double_support_step=max(0.0, 2.0 * (stance - 0.5)),
        weight_ratio=weight / PAPER_GRAVITY,
        closure_deg=float(closure),
        pose_step_length=pose_step_length(params, first_angles),
        trend_step_length=None if trend is None else trend / leg,
        table_step_length=table_step,
    )
