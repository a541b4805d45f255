"""Rows left out of a CSV trial: missing frames, filled briefly, else refused."""

from __future__ import annotations

import pathlib

import numpy as np
import pytest

from shared.demos.csv_import import read_csv
from shared.demos.missing_rows import missing_frames
from shared.errors import DemoFileError
from tests.test_demos_input_csv import MARKERS, arm_rows, write_csv


def test_a_long_run_of_deleted_rows_is_refused_naming_both_lines(
    tmp_path: pathlib.Path,
) -> None:
    """Rows 0.45-0.94 s deleted from a 100 Hz trial: a 0.5 s hole, refused
    naming the lines around it (it was joined, the wrist jumping across)."""
    rows = arm_rows(0, n=120)
    path = write_csv(tmp_path / "hole.csv", rows[:45] + rows[95:])
    with pytest.raises(DemoFileError) as caught:
        read_csv(path, MARKERS)
    assert caught.value.message == (
        f"{path}: trial 0: no rows between line 46 (t = 0.44 s) and line 47 "
        "(t = 0.95 s): 50 frames missing at the trial's step of 0.01 s "
        "(median), 0.5 s; the import fills missing frames for at most 0.1 s "
        "(a smoothing spline through the frames around them); export the rows "
        "between, or leave the trial out"
    )
    assert caught.value.evidence["line"] == 47
    assert caught.value.evidence["first_line"] == 46


def test_a_few_deleted_rows_are_filled_as_empty_cells_are(
    tmp_path: pathlib.Path,
) -> None:
    """Three rows deleted: the trial has its 30 frames back, every step
    0.01 s, and the wrist within 0.1 mm of the whole trial's."""
    rows = arm_rows(0)
    [whole], _ = read_csv(write_csv(tmp_path / "whole.csv", rows), MARKERS)
    notes: list[str] = []
    path = write_csv(tmp_path / "cut.csv", rows[:10] + rows[13:])
    [cut], _ = read_csv(path, MARKERS, report=notes.append)
    np.testing.assert_allclose(cut.times, whole.times, atol=1e-12)
    np.testing.assert_allclose(cut.wrist, whole.wrist, atol=1e-4)
    assert notes == [
        f"{path}: trial 0: filled 3 of 30 frames where a marker was missing "
        "(gaps of at most 0.1 s, by a smoothing spline), the first at frame 10 "
        "(t = 0.1 s, no row: between lines 11 and 12)"
    ]


def test_times_rounded_to_milliseconds_have_no_missing_frames() -> None:
    """400 Hz written to the millisecond steps 2 and 3 ms: no frame is
    missing, and the times come back as they were."""
    times = np.round(np.arange(200) / 400.0, 3)
    frames = missing_frames(times, list(range(2, 202)), "trial 0", "x.csv")
    np.testing.assert_array_equal(frames.times, times)
    np.testing.assert_array_equal(frames.rows, np.arange(200))


def test_a_frame_missing_at_an_uneven_rate_is_put_back_between() -> None:
    """One step of twice the median: one frame, halfway, between its rows."""
    times = np.array([0.0, 0.01, 0.02, 0.04, 0.05])
    frames = missing_frames(times, [2, 3, 4, 5, 6], "trial 0", "x.csv")
    np.testing.assert_allclose(frames.times, [0.0, 0.01, 0.02, 0.03, 0.04, 0.05])
    np.testing.assert_array_equal(frames.rows, [0, 1, 2, 4, 5])


def test_a_second_of_rows_missing_is_not_taken_for_frame_numbers(
    tmp_path: pathlib.Path,
) -> None:
    """39 rows at 100 Hz with 1 s missing after line 21: its rate over wide
    steps read 15.97 Hz and the import asked if the times were frame
    numbers; it is refused for the missing rows, naming lines 21 and 22."""
    rows = arm_rows(0, n=140)
    path = write_csv(tmp_path / "hole.csv", rows[:20] + rows[121:])
    with pytest.raises(DemoFileError) as caught:
        read_csv(path, MARKERS)
    assert caught.value.message == (
        f"{path}: trial 0: no rows between line 21 (t = 0.19 s) and line 22 "
        "(t = 1.21 s): 101 frames missing at the trial's step of 0.01 s "
        "(median), 1.01 s; the import fills missing frames for at most 0.1 s "
        "(a smoothing spline through the frames around them); export the rows "
        "between, or leave the trial out"
    )
