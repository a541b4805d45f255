"""A marker missing for a few frames is filled; at a trial's end, or for
long, the trial is refused naming the file, trial, marker and frames."""

from __future__ import annotations

import pathlib

import ezc3d
import numpy as np
import pytest

from shared.demos.c3d_import import read_c3d
from shared.demos.csv_import import read_csv
from shared.demos.markers import MarkerMap
from shared.errors import DemoFileError
from tests.test_demos_input_csv import MARKERS, arm_rows, write_csv

#: The wrist's three cells in a row of ``arm_rows``.
WRIST = slice(8, 11)


def _hide_wrist(rows: list[list[str]], frames: range) -> list[list[str]]:
    """``rows`` with the wrist's cells empty at ``frames``."""
    for k in frames:
        rows[k][WRIST] = ["", "", ""]
    return rows


def test_a_wrist_hidden_at_the_end_is_refused_naming_the_frames(
    tmp_path: pathlib.Path,
) -> None:
    """Hidden for the last 40 % of a trial, the wrist's last seen frame became
    the goal (48.5 mm short of it, the wrist still moving at 0.285 m/s) with
    only a note that frames were dropped."""
    path = write_csv(tmp_path / "rec.csv", _hide_wrist(arm_rows(0), range(18, 30)))
    with pytest.raises(DemoFileError) as caught:
        read_csv(path, MARKERS)
    assert caught.value.message == (
        f"{path}: subject 'rec', trial 0 (lines 2-31): marker 'RWRB' is missing "
        "from frame 18 (t = 0.18 s, line 20) to frame 29 (t = 0.29 s, line 31), "
        "the trial's last frame: the last frame is the reach's goal, which "
        "cannot be guessed from one side. Crop the trial to frames where every "
        "marker is seen, if the reach is whole there, or fill the gap in the "
        "capture software"
    )
    evidence = caught.value.evidence
    assert (evidence["marker"], evidence["first_frame"], evidence["last_frame"]) == (
        "RWRB",
        18,
        29,
    )


def test_one_missing_frame_at_the_start_is_refused(tmp_path: pathlib.Path) -> None:
    """The first frame is the reach's start: not guessed either."""
    path = write_csv(tmp_path / "rec.csv", _hide_wrist(arm_rows(0), range(0, 1)))
    with pytest.raises(DemoFileError, match=r"from frame 0 .* the trial's first frame"):
        read_csv(path, MARKERS)


@pytest.mark.parametrize(("hidden", "refused"), [(10, False), (11, True)])
def test_a_gap_in_the_middle_is_filled_up_to_a_tenth_of_a_second(
    tmp_path: pathlib.Path, hidden: int, refused: bool
) -> None:
    """10 frames at 100 Hz are filled, close to the positions hidden; 11 are
    refused. Joined without them, the trial had skipped 0.1 s of its reach."""
    rows = _hide_wrist(arm_rows(0), range(10, 10 + hidden))
    path = write_csv(tmp_path / "rec.csv", rows)
    if refused:
        with pytest.raises(DemoFileError) as caught:
            read_csv(path, MARKERS)
        assert caught.value.message == (
            f"{path}: subject 'rec', trial 0 (lines 2-31): marker 'RWRB' is "
            "missing for 0.11 s, from frame 10 (t = 0.1 s, line 12) to frame 20 "
            "(t = 0.2 s, line 22): the import fills a gap of at most 0.1 s (a "
            "smoothing spline through the frames around it); fill this one in the "
            "capture software, or leave the trial out"
        )
        return
    (filled,), _ = read_csv(path, MARKERS)
    (whole,), _ = read_csv(write_csv(tmp_path / "whole.csv", arm_rows(0)), MARKERS)
    np.testing.assert_array_equal(filled.times, whole.times)
    assert np.abs(filled.wrist - whole.wrist).max() < 1e-4  # [m], on NAO


def test_a_c3d_wrist_hidden_at_the_end_is_refused(tmp_path: pathlib.Path) -> None:
    """The same in a C3D file, its gap marked as C3D marks one (residual -1)."""
    rows = np.array([[float(v) for v in row[2:]] for row in arm_rows(0)])
    cloud = np.ones((4, 3, len(rows)))
    cloud[:3] = 1000.0 * rows.reshape(len(rows), 3, 3).transpose(2, 1, 0)
    residuals = np.zeros((1, 3, len(rows)))
    residuals[0, 2, 18:] = -1.0
    c3d = ezc3d.c3d()
    c3d["parameters"]["POINT"]["RATE"]["value"] = [100.0]
    c3d["parameters"]["POINT"]["LABELS"]["value"] = ("RSHO", "RELB", "RWRB")
    c3d["parameters"]["POINT"]["UNITS"]["value"] = ["mm"]
    c3d["data"]["points"] = cloud
    c3d["data"]["meta_points"]["residuals"] = residuals
    c3d["data"]["meta_points"]["camera_masks"] = np.zeros((7, 3, len(rows)), bool)
    path = tmp_path / "rec.c3d"
    c3d.write(str(path))
    markers = MarkerMap(shoulder="RSHO", elbow="RELB", wrist="RWRB", subject="P01")
    with pytest.raises(DemoFileError) as caught:
        read_c3d(path, markers)
    assert caught.value.message.startswith(
        f"{path}: subject 'P01', trial 0: marker 'RWRB' is missing from frame 18 "
        "(t = 0.18 s) to frame 29 (t = 0.29 s), the trial's last frame"
    )
