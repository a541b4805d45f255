"""CSV import: the documented column format, trials, units and clear errors."""

from __future__ import annotations

import csv
import pathlib

import numpy as np
import pytest

from shared.demos import nao_arm_size
from shared.demos.csv_import import read_csv
from shared.demos.markers import MarkerMap
from shared.demos.retarget import ArmTrack, retarget
from shared.errors import DemoFileError
from tests.test_demos_input_csv import arm_rows, write_csv

MARKERS = MarkerMap(shoulder="SHO", elbow="ELB", wrist="WRI", units="cm")
IN_METRES = MarkerMap(shoulder="RSHO", elbow="RELB", wrist="RWRB")


def _arm(n: int, phase: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Shoulder, elbow, wrist [m] of a simple swing, shape (n, 3) each."""
    angle = np.linspace(0.0, 1.2, n) + phase
    shoulder = np.tile([0.1, -0.2, 1.4], (n, 1))
    elbow = shoulder + 0.3 * np.stack(
        (np.sin(angle), np.zeros(n), -np.cos(angle)), axis=1
    )
    wrist = elbow + 0.25 * np.stack(
        (np.sin(angle + 0.6), np.zeros(n) + 0.05, -np.cos(angle + 0.6)), axis=1
    )
    return shoulder, elbow, wrist


def _write(path: pathlib.Path, trials: list[int], n: int = 30) -> None:
    header = ["time", "trial", "note"] + [
        f"{m}_{a}" for m in ("SHO", "ELB", "WRI") for a in "xyz"
    ]
    with open(path, "w", newline="") as stream:
        writer = csv.writer(stream)
        writer.writerow(header)
        for trial in trials:
            points = _arm(n, 0.1 * trial)
            for k in range(n):
                cells = [f"{k / 100:.2f}", trial, "x"]
                cells += [f"{100 * v:.6f}" for p in points for v in p[k]]
                writer.writerow(cells)


def test_csv_trials_are_read_retargeted_and_numbered(tmp_path: pathlib.Path) -> None:
    """Two trials in centimetres come back as two retargeted trials."""
    path = tmp_path / "rec.csv"
    _write(path, [3, 4])
    trials, person = read_csv(path, MARKERS)
    assert [t.trial for t in trials] == [3, 4]
    assert person.name == "rec"
    assert person.upper_arm == pytest.approx(0.3, abs=1e-5)
    for trial, number in zip(trials, (3, 4), strict=True):
        shoulder, elbow, wrist = _arm(30, 0.1 * number)
        expected = retarget(ArmTrack(shoulder, elbow, wrist), nao_arm_size("right"))
        np.testing.assert_allclose(trial.wrist, expected.wrist, atol=1e-7)
        assert trial.wrist_frame is None and trial.labels is None


def test_missing_column_is_named(tmp_path: pathlib.Path) -> None:
    """A marker without its columns: the error names the columns."""
    path = tmp_path / "rec.csv"
    _write(path, [0])
    markers = MARKERS.model_copy(update={"elbow": "RELB"})
    with pytest.raises(DemoFileError, match="RELB_x, RELB_y, RELB_z"):
        read_csv(path, markers)


def test_cells_that_are_not_numbers(tmp_path: pathlib.Path) -> None:
    """A cell that is not a number names its column and value."""
    path = tmp_path / "rec.csv"
    _write(path, [0])
    text = path.read_text().splitlines()
    text[5] = text[5].replace(text[5].split(",")[4], "oops", 1)
    path.write_text("\n".join(text) + "\n")
    with pytest.raises(DemoFileError, match="'oops', which is not a number"):
        read_csv(path, MARKERS)


def test_times_must_increase(tmp_path: pathlib.Path) -> None:
    """Repeated times within a trial are refused."""
    path = tmp_path / "rec.csv"
    _write(path, [0])
    lines = path.read_text().splitlines()
    lines[3] = lines[2]
    path.write_text("\n".join(lines) + "\n")
    with pytest.raises(DemoFileError, match="times of trial 0"):
        read_csv(path, MARKERS)


def test_empty_csv(tmp_path: pathlib.Path) -> None:
    """A header without rows is not a recording."""
    path = tmp_path / "rec.csv"
    path.write_text("time,SHO_x\n")
    with pytest.raises(DemoFileError, match="at least one data row"):
        read_csv(path, MARKERS)


def test_a_marker_absurdly_far_away_is_named(tmp_path: pathlib.Path) -> None:
    """A coordinate of 1e308 cm is no position (its length once overflowed in
    the retargeting): the error names the marker and the frame; an empty or
    NaN cell stays a missing sample, filled from the frames around."""
    path = tmp_path / "rec.csv"
    _write(path, [0])
    lines = path.read_text().splitlines()
    cells = lines[5].split(",")
    cells[4] = "1e308"  # SHO_y of the trial's fifth frame
    lines[5] = ",".join(cells)
    path.write_text("\n".join(lines) + "\n")
    with pytest.raises(DemoFileError, match=r"marker 'SHO' at frame 4 is at"):
        read_csv(path, MARKERS)
    cells[4] = "nan"
    lines[5] = ",".join(cells)
    path.write_text("\n".join(lines) + "\n")
    trials, _ = read_csv(path, MARKERS)
    assert len(trials[0].times) == 30


def _arms(path: pathlib.Path, scales: list[float]) -> pathlib.Path:
    """Trials 0, 1, ... of one swing, each trial's coordinates times its
    scale (a person of arms that much longer), in metres."""
    rows = [r for k, scale in enumerate(scales) for r in arm_rows(k, scale=scale)]
    return write_csv(path, rows)


def test_two_people_in_one_csv_are_refused_naming_the_trials(
    tmp_path: pathlib.Path,
) -> None:
    """Trials 2 and 3 of arms 25 % longer (a 1.95 m person beside a 1.55 m
    one): refused, naming them, their lines and both arms (they imported as
    one subject of median arms)."""
    path = _arms(tmp_path / "two.csv", [1.0, 1.0, 1.25, 1.25])
    with pytest.raises(DemoFileError) as caught:
        read_csv(path, IN_METRES)
    assert caught.value.message == (
        f"{path}: subject 'two': the arm of trials 2, 3 is not trial 0's: trial "
        "2 (lines 62-91) measures 0.375 + 0.312 m, trial 0 (lines 2-31) 0.300 + "
        "0.250 m, more than 10% apart: two people in one file? Give each person "
        'a file of their own and a name (the marker map\'s "subject")'
    )
    assert caught.value.evidence["trials"] == [2, 3]


def test_one_persons_arm_a_little_off_is_one_person(tmp_path: pathlib.Path) -> None:
    """Markers placed again (arms 5 % apart): one subject, of the median arm."""
    path = _arms(tmp_path / "one.csv", [1.0, 1.05, 1.05])
    trials, person = read_csv(path, IN_METRES)
    assert len(trials) == 3
    assert person.upper_arm == pytest.approx(0.315, abs=1e-5)


@pytest.mark.parametrize(("mark", "name"), [(";", "semicolons"), ("\t", "tabs")])
def test_a_header_of_another_delimiter_is_shown_with_a_hint(
    tmp_path: pathlib.Path, mark: str, name: str
) -> None:
    """A semicolon- or tab-separated file reads as one column: the error
    shows the header read and names its delimiter (it named only the
    columns it lacked)."""
    path = tmp_path / "rec.csv"
    _write(path, [0])
    path.write_text(path.read_text().replace(",", mark))
    with pytest.raises(DemoFileError) as caught:
        read_csv(path, MARKERS)
    cells = ["time", "trial", "note", "SHO_x", "SHO_y", "SHO_z", "ELB_x", "..."]
    header = mark.join(cells)  # its first 40 characters
    assert caught.value.message == (
        f"{path}: lacks the columns time, SHO_x, SHO_y, SHO_z, ELB_x, ELB_y, "
        f"ELB_z, WRI_x, WRI_y, WRI_z; its header reads 1 column: {header!r}: "
        f"its columns seem separated by {name}; the format's are separated by "
        "commas, with points for decimals (export it as comma-separated values)"
    )


def test_a_header_without_a_column_is_shown(tmp_path: pathlib.Path) -> None:
    """A comma-separated header lacking a marker: the error shows its first
    cells, and no delimiter hint."""
    path = tmp_path / "rec.csv"
    _write(path, [0])
    with pytest.raises(DemoFileError) as caught:
        read_csv(path, MARKERS.model_copy(update={"wrist": "RWRB"}))
    assert caught.value.message == (
        f"{path}: lacks the columns RWRB_x, RWRB_y, RWRB_z; its header reads 12 "
        "columns: 'time', 'trial', 'note', 'SHO_x', 'SHO_y', 'SHO_z', ..."
    )
