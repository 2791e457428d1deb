"""The WBDS loader: good files load, every kind of broken file or request is one line naming it."""

from __future__ import annotations

import shutil
from pathlib import Path

import numpy as np
import pytest

from ioc_bench.human.wbds import (
    ANGLE_COLUMNS,
    CYCLE_ROWS,
    KINETIC_COLUMNS,
    TABLE_NAME,
    WbdsData,
    WbdsDataError,
    read_table,
    shipped_folder,
)

SUBJECT, SPEED = "WBDS01", "T05"
ANG = f"{SUBJECT}walk{SPEED}ang.txt"
KNT = f"{SUBJECT}walk{SPEED}knt.txt"
STATIC = f"{SUBJECT}static1_head.txt"


@pytest.fixture
def folder(tmp_path: Path) -> Path:
    """A writable copy of subject 01's shipped files and the table."""
    src = shipped_folder()
    for name in [*(p.name for p in src.glob(f"{SUBJECT}*")), TABLE_NAME]:
        shutil.copy(src / name, tmp_path / name)
    return tmp_path


def _edit(path: Path, edit) -> None:
    lines = path.read_text().split("\n")
    path.write_text("\n".join(edit(lines)))


def _refused(folder: Path, match: str, subject: str = SUBJECT, speed: str = SPEED) -> str:
    with pytest.raises(WbdsDataError, match=match) as info:
        WbdsData(folder).trial(subject, speed)
    message = str(info.value)
    assert "\n" not in message
    return message


def test_shipped_subset_is_complete() -> None:
    data = WbdsData()
    assert data.subjects() == ["WBDS01", "WBDS02", "WBDS03"]
    for subject in data.subjects():
        assert data.speeds(subject) == ["T03", "T04", "T05", "T06"]
        for speed in data.speeds(subject):
            trial = data.trial(subject, speed)
            assert trial.row.speed_code == "V" + speed[-1]
            assert trial.static.frames == 2
    assert (shipped_folder() / "README.md").read_text().count("CC BY 4.0") >= 1


def test_a_good_trial_reads_every_column() -> None:
    trial = WbdsData().trial(SUBJECT, SPEED)
    for name in ANGLE_COLUMNS:
        assert trial.angles[name].shape == (CYCLE_ROWS,)
    for name in KINETIC_COLUMNS:
        assert trial.kinetics[name].shape == (CYCLE_ROWS,)
    # The table's row for subject 1 at V5 (1.21 m/s, 0.647 m, 112.9 steps/min).
    assert trial.row.speed == pytest.approx(1.21)
    assert trial.row.step_length == pytest.approx(0.6470907863836726)
    assert trial.row.cadence == pytest.approx(112.85266457680251)
    assert len(trial.subject_rows) == 6
    # First sample of RHipAngleZ at T05 as in the file.
    raw = (shipped_folder() / ANG).read_text().split("\n")
    header, first = raw[0].split("\t"), raw[1].split("\t")
    assert trial.angles["RHipAngleZ"][0] == float(first[header.index("RHipAngleZ")])


def test_a_copied_folder_reads_like_the_shipped_one(folder: Path) -> None:
    mine, shipped = WbdsData(folder).trial(SUBJECT, SPEED), WbdsData().trial(SUBJECT, SPEED)
    assert np.array_equal(mine.angles["LKneeAngleZ"], shipped.angles["LKneeAngleZ"])


def test_truncated_row(folder: Path) -> None:
    _edit(folder / ANG, lambda lines: [*lines[:10], "\t".join(lines[10].split("\t")[:-3]), *lines[11:]])
    assert ANG in _refused(folder, "line 11 has 28 fields, its header has 31")


def test_partial_file(folder: Path) -> None:
    _edit(folder / KNT, lambda lines: lines[:60])
    assert KNT in _refused(folder, "59 data rows, a mean cycle has 101")


def test_non_number(folder: Path) -> None:
    def corrupt(lines):
        fields = lines[5].split("\t")
        fields[3] = "1.2.3"
        return [*lines[:5], "\t".join(fields), *lines[6:]]

    _edit(folder / ANG, corrupt)
    assert ANG in _refused(folder, r"line 6: '1.2.3' is not a number")


def test_non_finite_value(folder: Path) -> None:
    def corrupt(lines):
        fields = lines[7].split("\t")
        fields[2] = "nan"
        return [*lines[:7], "\t".join(fields), *lines[8:]]

    _edit(folder / KNT, corrupt)
    _refused(folder, "line 8 has a non-finite value")


def _unload(folder: Path, side: str, rows: range, axes: str = "XYZ") -> None:
    """Mark ``side``'s ground force NaN in ``rows`` (the data set's unloaded foot), where it is zero."""

    def mark(lines):
        header = lines[0].split("\t")
        cols = [header.index(f"{side}GRF{axis}") for axis in axes]
        out = [lines[0]]
        for i, line in enumerate(lines[1:]):
            fields = line.split("\t")
            if i in rows and len(fields) == len(header):
                for j in cols:
                    fields[j] = "NaN"
            out.append("\t".join(fields))
        return out

    _edit(folder / KNT, mark)


def _zero_force_rows(side: str) -> range:
    """The rows of the shipped file where ``side``'s vertical force is zero (its swing)."""
    cycle = WbdsData().trial(SUBJECT, SPEED).kinetics
    zero = np.flatnonzero(cycle[f"{side}GRFY"] == 0)
    return range(int(zero.min()), int(zero.max()) + 1)


def test_an_unloaded_foot_marked_nan_reads_as_zero_force(folder: Path) -> None:
    """Older adults' files of the data set mark the swinging foot's force NaN: that is zero force."""
    swing = _zero_force_rows("R")
    assert len(swing) > 20
    _unload(folder, "R", swing)
    read = WbdsData(folder).trial(SUBJECT, SPEED).kinetics
    shipped = WbdsData().trial(SUBJECT, SPEED).kinetics
    for name in KINETIC_COLUMNS:
        assert np.array_equal(read[name], shipped[name]), name


@pytest.mark.parametrize(
    ("rows", "axes", "match"),
    [
        (range(10, 12), "X", "NaN in some axes and not in others"),
        (range(0, 70), "XYZ", "not one swing of the stride"),
        (range(-1, -1), "XYZ", None),  # no NaN at all: reads
    ],
)
def test_nan_forces_that_are_no_swing_are_refused(folder: Path, rows, axes, match) -> None:
    _unload(folder, "L", rows, axes)
    if match is None:
        WbdsData(folder).trial(SUBJECT, SPEED)
    else:
        _refused(folder, match)


def test_nan_in_two_runs_or_outside_the_forces_is_refused(folder: Path) -> None:
    _unload(folder, "L", range(5, 10))
    _unload(folder, "L", range(30, 35))
    _refused(folder, "not one swing")
    (folder / KNT).write_text((shipped_folder() / KNT).read_text())
    _edit(folder / ANG, lambda lines: [*lines[:5], lines[5].replace(lines[5].split("\t")[3], "NaN", 1), *lines[6:]])
    _refused(folder, "non-finite value")


def test_missing_column(folder: Path) -> None:
    _edit(folder / ANG, lambda lines: [lines[0].replace("RKneeAngleZ", "RKneeAngleW"), *lines[1:]])
    assert ANG in _refused(folder, "lacks column.*RKneeAngleZ")


def test_wrong_time_column(folder: Path) -> None:
    def shift(lines):
        fields = lines[3].split("\t")
        fields[0] = "7"
        return [*lines[:3], "\t".join(fields), *lines[4:]]

    _edit(folder / KNT, shift)
    _refused(folder, "Time column is not 0, 1, ..., 100")


def test_empty_file(folder: Path) -> None:
    (folder / KNT).write_text("")
    assert KNT in _refused(folder, "is empty")


def test_missing_file(folder: Path) -> None:
    (folder / KNT).unlink()
    _refused(folder, f"has no {KNT}")


def test_missing_static(folder: Path) -> None:
    (folder / STATIC).unlink()
    _refused(folder, "no static trial for WBDS01")


def test_static_without_a_marker(folder: Path) -> None:
    _edit(folder / STATIC, lambda lines: [lines[0].replace("R.Knee.MedialX", "R.Knee.MedX"), *lines[1:]])
    assert STATIC in _refused(folder, r"lacks column.*R\.Knee\.MedialX")


def test_static_without_frames(folder: Path) -> None:
    _edit(folder / STATIC, lambda lines: lines[:1])
    _refused(folder, "has no frames")


def test_the_whole_static_trial_is_accepted_too(folder: Path) -> None:
    (folder / STATIC).rename(folder / f"{SUBJECT}static1.txt")
    assert WbdsData(folder).trial(SUBJECT, SPEED).static.frames == 2


def test_unknown_subject_and_speed_codes(folder: Path) -> None:
    _refused(folder, "unknown subject code 'WBDS1'", subject="WBDS1")
    _refused(folder, "unknown speed code 'T5'", speed="T5")
    _refused(folder, "unknown speed code 'O1'", speed="O1")


def test_a_subject_not_in_the_folder(folder: Path) -> None:
    message = _refused(folder, "has no WBDS02walkT05ang.txt", subject="WBDS02")
    assert "subjects here: WBDS01" in message


def test_a_speed_not_in_the_folder(folder: Path) -> None:
    message = _refused(folder, "has no WBDS01walkT01ang.txt", speed="T01")
    assert "WBDS01 has T03, T04, T05, T06" in message


def test_a_folder_without_the_files(tmp_path: Path) -> None:
    _refused(tmp_path, "has no WBDS01walkT05ang.txt")
    with pytest.raises(WbdsDataError, match="does not exist or is not a directory"):
        WbdsData(tmp_path / "nowhere")


def test_a_subject_without_a_table_row(folder: Path) -> None:
    _edit(folder / TABLE_NAME, lambda lines: [line for line in lines if not line.startswith("1,")])
    _refused(folder, "has no row for subject 1 at V5")


def test_a_speed_without_a_table_row(folder: Path) -> None:
    # T07 exists in the whole data set but the table stops at V6.
    for kind in ("ang", "knt"):
        shutil.copy(folder / f"{SUBJECT}walkT05{kind}.txt", folder / f"{SUBJECT}walkT07{kind}.txt")
    _refused(folder, "has no row for subject 1 at V7", speed="T07")


def test_a_folder_without_a_table_uses_the_shipped_one(folder: Path) -> None:
    (folder / TABLE_NAME).unlink()
    data = WbdsData(folder)
    assert data.table_path == shipped_folder() / TABLE_NAME
    assert data.trial(SUBJECT, SPEED).row.subject == 1


def test_table_checks(tmp_path: Path) -> None:
    good = (shipped_folder() / TABLE_NAME).read_text().split("\n")
    path = tmp_path / TABLE_NAME

    def refused(lines, match):
        path.write_text("\n".join(lines))
        with pytest.raises(WbdsDataError, match=match):
            read_table(path)

    refused([good[0].replace("StepLength", "Step")], "lacks column.*StepLength")
    refused([good[0], good[1].replace(",0.49,", ",fast,")], "line 2: Speed 'fast' is not a number")
    refused([good[0], good[1].replace(",0.49,", ",-0.49,")], "Speed must be a positive number")
    refused([good[0], good[1].replace(",V1,", ",V9,")], "SpeedCat 'V9' is not V1..V8")
    refused([good[0], good[1].rsplit(",", 1)[0]], "line 2 has 15 fields")
    refused([good[0], good[1].replace(",0.49,", ",0.69,")], "StepLength x Cadence gives 0.491 m/s, Speed says 0.690")
    changed = good[1].replace(",67.79661016949153,", ",67.8,")
    refused([good[0], good[1], changed], "line 3: a second, different row for subject 1 at V1")
    path.write_text("\n".join([good[0], good[1], good[1]]))
    assert len(read_table(path)) == 1  # an identical duplicate is harmless


def test_a_non_ascii_file(folder: Path) -> None:
    (folder / ANG).write_bytes(b"\xff\xfe" + (folder / ANG).read_bytes())
    _refused(folder, "is not an ASCII text file")
