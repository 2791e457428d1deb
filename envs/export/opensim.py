"""One full stride as an OpenSim storage file (``.sto``), named as OpenSim's planar gait models name it.

**Coordinates.** The walker's coordinates that have a counterpart in OpenSim's gait models
(``gait10dof18musc``, the planar one, and ``gait2392``/``gait2354``) get its name; the
walker's torso (head, arms and trunk in one segment) stands in for the pelvis, leg ``a``
for the right leg and leg ``b`` for the left:

===============  =============================  ==========================================
OpenSim          the walker (MuJoCo joint)      conversion
===============  =============================  ==========================================
pelvis_tilt      torso angle (``rooty``)        ``-rooty``
pelvis_tx        hip x (``rootx``)              ``rootx`` (m)
pelvis_ty        hip height (``rootz``)         ``rootz`` (m)
hip_flexion_r    hip of leg a (``hip_a``)       ``-hip_a``
knee_angle_r     knee of leg a (``knee_a``)     ``-knee_a``
hip_flexion_l    hip of leg b (``hip_b``)       ``-hip_b``
knee_angle_l     knee of leg b (``knee_b``)     ``-knee_b``
===============  =============================  ==========================================

**Signs.** OpenSim's frames have x forward, y up and z to the right, and every sagittal
coordinate is a rotation about z (right-handed): a positive ``pelvis_tilt`` tilts the
pelvis's top backwards, a positive ``hip_flexion`` swings the thigh forward (flexion), and
``knee_angle`` is negative in flexion (its range in the models is -120° to 10°). The
walker's angles are rotations about MuJoCo's y axis, which points to the walker's left
(x forward, z up): positive leans a segment's top forward, so a positive hip angle is
extension and a positive knee angle flexion. The axes are opposite, hence every angle's
minus sign. Translations keep their sign (x forward, height up).

**What differs from a model's own coordinates.** ``pelvis_tx``/``pelvis_ty`` are the
walker's hip joint, where both legs attach; an OpenSim pelvis's origin lies behind and
above its hip joints (0.07 m back, 0.066 m up in ``gait10dof18musc``), so a model driven by
this file walks with its pelvis origin on the walker's hip path. The walker has point
feet and one rigid trunk: there is no ``ankle_angle`` or ``lumbar_extension`` column, and
a model keeps those coordinates at its default values.

**The file.** OpenSim's storage format (OpenSim documentation, "Storage (.sto) Files"):
a header of the name (``Coordinates``, as OpenSim's inverse kinematics writes), then
``version=1``, ``nRows=``, ``nColumns=`` (counting ``time``), ``inDegrees=yes|no`` and
``endheader``; then a tab-separated line of column labels starting with ``time`` and
``nRows`` tab-separated rows of numbers. Times in s from the first heel strike of leg a
(the right), one row per sample of :func:`envs.export.joints.stride_series`; lengths in
m; angles in rad (``inDegrees=no``) or degrees (``inDegrees=yes``).
"""

from __future__ import annotations

import math
import os
from pathlib import Path

import numpy as np

from envs.export.joints import DEFAULT_LEG_LENGTH, DEFAULT_RATE, JointSeries, stride_series
from ioc_bench.demo import Demonstration
from ioc_bench.fileio import atomic_write_text
from ioc_bench.paths import check_output_file

#: (OpenSim coordinate, MuJoCo joint, sign, is an angle), in the order the file's columns take.
COORDINATES: tuple[tuple[str, str, float, bool], ...] = (
    ("pelvis_tilt", "rooty", -1.0, True),
    ("pelvis_tx", "rootx", 1.0, False),
    ("pelvis_ty", "rootz", 1.0, False),
    ("hip_flexion_r", "hip_a", -1.0, True),
    ("knee_angle_r", "knee_a", -1.0, True),
    ("hip_flexion_l", "hip_b", -1.0, True),
    ("knee_angle_l", "knee_b", -1.0, True),
)
#: The storage's name (its first line).
STORAGE_NAME = "Coordinates"
#: Significant digits of every number written.
DIGITS = 10


def coordinate_table(series: JointSeries, degrees: bool = False) -> tuple[tuple[str, ...], np.ndarray]:
    """Column labels (``time`` first) and the (n, 8) table of a stride in OpenSim's coordinates."""
    columns = [series.times]
    for _, joint, sign, angle in COORDINATES:
        values = sign * series.column(joint)
        columns.append(np.degrees(values) if angle and degrees else values)
    return ("time", *(c[0] for c in COORDINATES)), np.column_stack(columns)


def sto_text(series: JointSeries, degrees: bool = False) -> str:
    """The storage file's text (see the module docstring)."""
    labels, table = coordinate_table(series, degrees)
    header = [
        STORAGE_NAME,
        "version=1",
        f"nRows={table.shape[0]}",
        f"nColumns={table.shape[1]}",
        f"inDegrees={'yes' if degrees else 'no'}",
        "endheader",
        "\t".join(labels),
    ]
    rows = ["\t".join(_number(v) for v in row) for row in table]
    return "\n".join(header + rows) + "\n"


def write_sto(
    demo: Demonstration,
    path: str | os.PathLike,
    rate: float = DEFAULT_RATE,
    leg_length: float = DEFAULT_LEG_LENGTH,
    degrees: bool = False,
) -> tuple[Path, JointSeries]:
    """Write one full stride of ``demo`` as an OpenSim ``.sto`` (atomically); returns the path and the series.

    Raises:
        ValueError: for a path that cannot be written, and as :func:`~envs.export.joints.stride_series`.
    """
    path = check_output_file(path)
    series = stride_series(demo, rate, leg_length)
    atomic_write_text(path, sto_text(series, degrees))
    return path, series


def _number(value: float) -> str:
    if not math.isfinite(value):
        raise ValueError(f"a stride's coordinate is not finite: {value}")
    text = f"{value:.{DIGITS}g}"
    return "0" if text == "-0" else text
