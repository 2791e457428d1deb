"""Reading the WBDS walking data set (Fukuchi, Fukuchi & Duarte 2018) in its ASCII layout.

A folder of the layout holds, per subject ``WBDSnn`` and treadmill speed ``Tmm``:

- ``WBDSnnwalkTmmang.txt``: the mean gait cycle (101 rows, ``Time`` 0..100 % of the stride)
  of joint angles in degrees, ``<R|L><Pelvis|Hip|Knee|Ankle>Angle<X|Y|Z>``, Z sagittal;
- ``WBDSnnwalkTmmknt.txt``: the same cycle of joint moments (N m/kg) and ground reaction
  forces (N/kg), ``<R|L><Hip|Knee|Ankle>Moment<X|Y|Z>`` and ``<R|L>GRF<X|Y|Z>``;
- ``WBDSnnstatic1_head.txt`` (or the whole ``WBDSnnstatic1.txt``): marker positions (mm)
  while standing, one row per frame;

and, once for the folder, the laboratory's per-subject, per-speed table
``BMClab_H2A_stats_input_51subs.csv`` (height, mass, belt speed, step length, cadence;
``SpeedCat`` ``Vn`` is treadmill speed ``T0n``). The shipped subset lives in
``ioc_bench/human/data/wbds`` (see its ``README.md`` for the attribution); a user with the
whole data set points :class:`WbdsData` at any folder of the same layout. If that folder
has no table, the shipped copy (which covers every WBDS subject) is used.

Every file is checked when it is read: a missing, malformed, partial, wrong-shaped or
non-numeric file, an unknown subject or speed code, or a subject without a table row is
refused with a one-line :class:`WbdsDataError` naming the file, before anything is solved.
"""

from __future__ import annotations

import csv
import math
import os
import re
from dataclasses import dataclass
from importlib import resources
from pathlib import Path

import numpy as np

#: The laboratory's table of subjects and speeds (BMClab/datasets, H2A).
TABLE_NAME = "BMClab_H2A_stats_input_51subs.csv"
#: Rows of a mean-cycle file: 0..100 % of the stride.
CYCLE_ROWS = 101
#: Columns of an angle file this package reads (each must be present).
ANGLE_COLUMNS: tuple[str, ...] = tuple(
    f"{side}{joint}AngleZ" for side in "RL" for joint in ("Pelvis", "Hip", "Knee", "Ankle")
)
#: Columns of a kinetics file this package reads.
KINETIC_COLUMNS: tuple[str, ...] = tuple(
    [f"{side}{joint}MomentZ" for side in "RL" for joint in ("Hip", "Knee", "Ankle")]
    + [f"{side}GRF{axis}" for side in "RL" for axis in "XY"]
)
#: Static markers the subject's segment lengths are built from.
STATIC_MARKERS: tuple[str, ...] = tuple(
    f"{side}.{name}"
    for side in "RL"
    for name in ("ASIS", "PSIS", "Knee", "Knee.Medial", "Ankle", "Ankle.Medial", "MT2", "Heel")
)
#: Table columns this package reads.
TABLE_COLUMNS: tuple[str, ...] = (
    "Subject",
    "Gender",
    "Height",
    "Mass",
    "LegLength",
    "SpeedCat",
    "Speed",
    "StepLength",
    "Cadence",
)
#: Largest relative mismatch between StepLength x Cadence and Speed in a table row (the
#: shipped table's worst is 3.4 %).
SPEED_MISMATCH = 0.10
_SUBJECT = re.compile(r"WBDS(\d\d)")
_SPEED = re.compile(r"T0([1-8])")
_TRIAL_FILE = re.compile(r"(WBDS\d\d)walk(T0[1-8])ang\.txt")


class WbdsDataError(ValueError):
    """A WBDS file or request that cannot be used; the message is one line naming it."""


@dataclass(frozen=True, eq=False)
class MeanCycle:
    """One mean-cycle file: every column over 0..100 % of the stride.

    Attributes:
        path: the file read.
        columns: column name -> (101,) values, in the file's units.
    """

    path: Path
    columns: dict[str, np.ndarray]

    def __getitem__(self, name: str) -> np.ndarray:
        return self.columns[name]


@dataclass(frozen=True)
class TableRow:
    """The laboratory's record of one subject at one treadmill speed (SI units).

    Attributes:
        subject: subject number (the WBDS number).
        speed_code: ``Vn`` of the table (treadmill speed ``T0n``).
        gender: ``M`` or ``F``.
        height: body height, m.
        mass: body mass as listed, kg.
        leg_length: the laboratory's leg length, m.
        speed: belt speed, m/s.
        step_length: mean step length, m.
        cadence: steps per minute.
    """

    subject: int
    speed_code: str
    gender: str
    height: float
    mass: float
    leg_length: float
    speed: float
    step_length: float
    cadence: float

    @property
    def step_time(self) -> float:
        """Seconds per step, from the cadence."""
        return 60.0 / self.cadence


@dataclass(frozen=True, eq=False)
class StaticMarkers:
    """Marker positions of a standing trial, averaged over its frames.

    Attributes:
        path: the file read.
        frames: how many frames were averaged.
        positions: marker name (e.g. ``R.Knee``) -> (3,) position in mm, lab axes
            X forward, Y up, Z to the right.
    """

    path: Path
    frames: int
    positions: dict[str, np.ndarray]

    def __getitem__(self, name: str) -> np.ndarray:
        return self.positions[name]


@dataclass(frozen=True, eq=False)
class WbdsTrial:
    """Everything read for one subject at one treadmill speed, every file checked.

    Attributes:
        subject: ``WBDSnn``.
        speed_code: ``T0n``.
        angles: the ``*ang.txt`` mean cycle.
        kinetics: the ``*knt.txt`` mean cycle.
        static: the standing trial's markers.
        row: the table's row for this subject and speed.
        subject_rows: the table's rows of this subject at every speed (for checks of the
            row against the subject's trend).
    """

    subject: str
    speed_code: str
    angles: MeanCycle
    kinetics: MeanCycle
    static: StaticMarkers
    row: TableRow
    subject_rows: tuple[TableRow, ...]


def shipped_folder() -> Path:
    """The folder of the WBDS subset shipped inside the package."""
    return Path(str(resources.files("ioc_bench.human").joinpath("data", "wbds")))


def subject_number(subject: str) -> int:
    """``WBDSnn`` -> nn; one-line error for anything else."""
    match = _SUBJECT.fullmatch(subject) if isinstance(subject, str) else None
    if match is None:
        raise WbdsDataError(f"unknown subject code {subject!r}: expected WBDSnn, e.g. WBDS01")
    return int(match.group(1))


def table_speed_code(speed_code: str) -> str:
    """Treadmill code ``T0n`` -> the table's ``Vn``; one-line error for anything else."""
    match = _SPEED.fullmatch(speed_code) if isinstance(speed_code, str) else None
    if match is None:
        raise WbdsDataError(f"unknown speed code {speed_code!r}: expected a treadmill speed T01..T08, e.g. T05")
    return f"V{match.group(1)}"


class WbdsData:
    """A folder of the WBDS ASCII layout (default: the shipped subset).

    Args:
        folder: the folder; None for the subset shipped in the package.
        table: the laboratory's table; default ``folder/BMClab_H2A_stats_input_51subs.csv``
            if present, else the shipped copy.

    Raises:
        WbdsDataError: the folder does not exist or is not a directory.
    """

    def __init__(self, folder: str | os.PathLike | None = None, table: str | os.PathLike | None = None):
        self.folder = shipped_folder() if folder is None else Path(folder)
        if not self.folder.is_dir():
            raise WbdsDataError(f"WBDS data folder {self.folder} does not exist or is not a directory")
        if table is None:
            own = self.folder / TABLE_NAME
            table = own if own.is_file() else shipped_folder() / TABLE_NAME
        self.table_path = Path(table)
        self._table: dict[tuple[int, str], TableRow] | None = None

    # -- what the folder holds -------------------------------------------------------
    def trials(self) -> list[tuple[str, str]]:
        """(subject, speed code) of every treadmill angle file in the folder, sorted."""
        found = [_TRIAL_FILE.fullmatch(p.name) for p in self.folder.iterdir()]
        return sorted((m.group(1), m.group(2)) for m in found if m)

    def subjects(self) -> list[str]:
        return sorted({s for s, _ in self.trials()})

    def speeds(self, subject: str) -> list[str]:
        subject_number(subject)
        return [t for s, t in self.trials() if s == subject]

    # -- reading, checked --------------------------------------------------------------
    def trial(self, subject: str, speed_code: str) -> WbdsTrial:
        """Read and check every file of one subject at one speed (see the module docstring)."""
        number = subject_number(subject)
        category = table_speed_code(speed_code)
        ang = self._require(f"{subject}walk{speed_code}ang.txt", subject)
        knt = self._require(f"{subject}walk{speed_code}knt.txt", subject)
        static = self.static_path(subject)
        table = self.table()
        if (number, category) not in table:
            raise WbdsDataError(
                f"{self.table_path.name} has no row for subject {number} at {category} ({subject} {speed_code})"
            )
        rows = tuple(table[k] for k in sorted(table) if k[0] == number)
        return WbdsTrial(
            subject=subject,
            speed_code=speed_code,
            angles=read_mean_cycle(ang, ANGLE_COLUMNS),
            kinetics=read_mean_cycle(knt, KINETIC_COLUMNS),
            static=read_static(static),
            row=table[(number, category)],
            subject_rows=rows,
        )

    def static_path(self, subject: str) -> Path:
        """The subject's standing trial: ``WBDSnnstatic1_head.txt`` or ``WBDSnnstatic1.txt``."""
        subject_number(subject)
        for name in (f"{subject}static1_head.txt", f"{subject}static1.txt"):
            if (self.folder / name).is_file():
                return self.folder / name
        raise WbdsDataError(
            f"{self.folder} has no static trial for {subject} ({subject}static1_head.txt or {subject}static1.txt)"
        )

    def table(self) -> dict[tuple[int, str], TableRow]:
        """The laboratory's table, keyed by (subject number, ``Vn``); read and checked once."""
        if self._table is None:
            self._table = read_table(self.table_path)
        return self._table

    def _require(self, name: str, subject: str) -> Path:
        path = self.folder / name
        if not path.is_file():
            have = self.speeds(subject)
            hint = f"; {subject} has {', '.join(have)}" if have else f"; subjects here: {', '.join(self.subjects())}"
            raise WbdsDataError(f"{self.folder} has no {name}{hint}")
        return path


# -- the three file kinds ------------------------------------------------------------------


def _lines(path: Path) -> list[str]:
    try:
        text = path.read_text(encoding="ascii")
    except FileNotFoundError:
        raise WbdsDataError(f"{path} does not exist") from None
    except UnicodeDecodeError:
        raise WbdsDataError(f"{path.name} is not an ASCII text file") from None
    except OSError as exc:
        raise WbdsDataError(f"cannot read {path}: {exc.strerror}") from None
    lines = [line.rstrip("\r") for line in text.split("\n")]
    while lines and not lines[-1].strip():
        lines.pop()
    return lines


def _numeric_rows(path: Path, lines: list[str], n_columns: int, may_be_nan: frozenset[int] = frozenset()) -> np.ndarray:
    """The tab-separated data lines as a (rows, n_columns) array of finite numbers (``NaN``
    allowed in the columns ``may_be_nan``)."""
    rows = []
    for i, line in enumerate(lines, start=2):
        fields = line.split("\t")
        if len(fields) != n_columns:
            raise WbdsDataError(f"{path.name} line {i} has {len(fields)} fields, its header has {n_columns}")
        try:
            values = [float(f) for f in fields]
        except ValueError:
            bad = next(f for f in fields if not _is_float(f))
            raise WbdsDataError(f"{path.name} line {i}: {bad!r} is not a number") from None
        if not all(math.isfinite(v) or (j in may_be_nan and math.isnan(v)) for j, v in enumerate(values)):
            raise WbdsDataError(f"{path.name} line {i} has a non-finite value")
        rows.append(values)
    return np.array(rows, dtype=float).reshape(len(rows), n_columns)


def _is_float(text: str) -> bool:
    try:
        float(text)
    except ValueError:
        return False
    return True


def _header(path: Path, lines: list[str], required: tuple[str, ...]) -> list[str]:
    if not lines:
        raise WbdsDataError(f"{path.name} is empty")
    header = lines[0].split("\t")
    missing = [c for c in required if c not in header]
    if missing:
        shown = ", ".join(missing[:4]) + (f" and {len(missing) - 4} more" if len(missing) > 4 else "")
        raise WbdsDataError(f"{path.name} lacks column(s) {shown}")
    if len(set(header)) != len(header):
        raise WbdsDataError(f"{path.name} has duplicate column names")
    return header


#: Ground-force columns: the data set marks a foot's force ``NaN`` while that foot is off the
#: ground (its older adults' files do; the young adults' hold zeros there).
_FORCE = re.compile(r"([RL])GRF[XYZ]")
#: Most of a stride a foot may be marked unloaded (walking keeps each foot down about 60 %).
MAX_UNLOADED = 0.6


def read_mean_cycle(path: str | os.PathLike, required: tuple[str, ...]) -> MeanCycle:
    """A mean-cycle file: a ``Time`` column 0..100 and ``required`` columns, 101 numeric rows.

    ``NaN`` is read only where the data set uses it, in a foot's ground-force columns while
    that foot is unloaded: one run of rows (the swing, maybe across the cycle's ends), the
    same rows in every axis of that foot, under :data:`MAX_UNLOADED` of the stride. It is
    read as zero force. Any other ``NaN`` is a damaged file (one line naming it).
    """
    path = Path(path)
    lines = _lines(path)
    header = _header(path, lines, ("Time", *required))
    forces = frozenset(j for j, name in enumerate(header) if _FORCE.fullmatch(name))
    data = _numeric_rows(path, lines[1:], len(header), forces)
    _unloaded_feet(path, header, data)
    if data.shape[0] != CYCLE_ROWS:
        raise WbdsDataError(f"{path.name} has {data.shape[0]} data rows, a mean cycle has {CYCLE_ROWS} (0..100 %)")
    time = data[:, header.index("Time")]
    if not np.allclose(time, np.arange(CYCLE_ROWS), atol=1e-6):
        raise WbdsDataError(f"{path.name}: the Time column is not 0, 1, ..., 100 (% of the stride)")
    return MeanCycle(path, {name: data[:, j] for j, name in enumerate(header)})


def _unloaded_feet(path: Path, header: list[str], data: np.ndarray) -> None:
    """Check the ``NaN`` of every foot's force columns (see :func:`read_mean_cycle`) and read
    them as zero force, in place."""
    for side in "RL":
        cols = [j for j, name in enumerate(header) if _FORCE.fullmatch(name) and name[0] == side]
        if not cols:
            continue
        nan = np.isnan(data[:, cols])
        off = nan[:, 0]
        if not nan.any():
            continue
        if not np.all(nan == off[:, None]):
            raise WbdsDataError(f"{path.name}: the {side} foot's force is NaN in some axes and not in others")
        if off.mean() > MAX_UNLOADED or _runs(off) > 1:
            raise WbdsDataError(
                f"{path.name}: the {side} foot's force is NaN in {int(off.sum())} rows, not one swing of the stride"
            )
        data[np.ix_(off, cols)] = 0.0


def _runs(flags: np.ndarray) -> int:
    """How many runs of True ``flags`` holds, counting one that wraps around the cycle once."""
    starts = int(np.sum(flags & ~np.roll(flags, 1)))
    return starts if not flags.all() else 1


def read_static(path: str | os.PathLike) -> StaticMarkers:
    """A standing trial: ``Time`` and X/Y/Z columns of :data:`STATIC_MARKERS`, >= 1 frame."""
    path = Path(path)
    lines = _lines(path)
    required = tuple(f"{m}{axis}" for m in STATIC_MARKERS for axis in "XYZ")
    header = _header(path, lines, ("Time", *required))
    data = _numeric_rows(path, lines[1:], len(header))
    if data.shape[0] == 0:
        raise WbdsDataError(f"{path.name} has no frames")
    mean = data.mean(axis=0)
    positions = {m: np.array([mean[header.index(m + axis)] for axis in "XYZ"]) for m in STATIC_MARKERS}
    return StaticMarkers(path, data.shape[0], positions)


def read_table(path: str | os.PathLike) -> dict[tuple[int, str], TableRow]:
    """The laboratory's table; every row checked, identical duplicates merged, conflicting ones refused."""
    path = Path(path)
    lines = _lines(path)
    if not lines:
        raise WbdsDataError(f"{path.name} is empty")
    reader = csv.reader(lines)
    header = next(reader)
    missing = [c for c in TABLE_COLUMNS if c not in header]
    if missing:
        raise WbdsDataError(f"{path.name} lacks column(s) {', '.join(missing)}")
    out: dict[tuple[int, str], TableRow] = {}
    for i, fields in enumerate(reader, start=2):
        if len(fields) != len(header):
            raise WbdsDataError(f"{path.name} line {i} has {len(fields)} fields, its header has {len(header)}")
        row = _table_row(path, i, dict(zip(header, fields)))
        key = (row.subject, row.speed_code)
        if key in out and out[key] != row:
            raise WbdsDataError(f"{path.name} line {i}: a second, different row for subject {key[0]} at {key[1]}")
        out[key] = row
    return out


def _table_row(path: Path, line: int, raw: dict[str, str]) -> TableRow:
    try:
        subject = int(raw["Subject"])
    except ValueError:
        raise WbdsDataError(f"{path.name} line {line}: Subject {raw['Subject']!r} is not an integer") from None
    if not re.fullmatch(r"V[1-8]", raw["SpeedCat"]):
        raise WbdsDataError(f"{path.name} line {line}: SpeedCat {raw['SpeedCat']!r} is not V1..V8")
    values = {}
    for name in ("Height", "Mass", "LegLength", "Speed", "StepLength", "Cadence"):
        try:
            value = float(raw[name])
        except ValueError:
            raise WbdsDataError(f"{path.name} line {line}: {name} {raw[name]!r} is not a number") from None
        if not (math.isfinite(value) and value > 0):
            raise WbdsDataError(f"{path.name} line {line}: {name} must be a positive number, got {raw[name]!r}")
        values[name] = value
    implied = values["StepLength"] * values["Cadence"] / 60.0
    if abs(implied / values["Speed"] - 1.0) > SPEED_MISMATCH:
        raise WbdsDataError(
            f"{path.name} line {line}: StepLength x Cadence gives {implied:.3f} m/s, Speed says {values['Speed']:.3f}"
        )
    return TableRow(
        subject=subject,
        speed_code=raw["SpeedCat"],
        gender=raw["Gender"].strip(),
        height=values["Height"],
        mass=values["Mass"],
        leg_length=values["LegLength"],
        speed=values["Speed"],
        step_length=values["StepLength"],
        cadence=values["Cadence"],
    )
