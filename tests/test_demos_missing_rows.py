"""Rows left out of a CSV trial: missing frames, filled briefly, else refused."""

from __future__ import annotations

import pathlib

import numpy as np
import pytest

from shared.demos.csv_import import read_csv
from shared.demos.missing_rows import missing_frames
from shared.demos.sample_rate import fitted_rate
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


def _rounded_rows(rate: float, n: int) -> list[list[str]]:
    """``arm_rows`` of one trial at ``rate`` [Hz], its times written to the ms."""
    rows = arm_rows(0, n=n)
    for k, row in enumerate(rows):
        row[0] = f"{k / rate:.3f}"
    return rows


@pytest.mark.parametrize(("rate", "rows"), [(700.0, 910), (960.0, 1248)])
def test_times_rounded_to_the_ms_above_500_hz_have_no_missing_frames(
    tmp_path: pathlib.Path, rate: float, rows: int
) -> None:
    """Above 500 Hz the ms steps are 1 and 2 ms about a 1 ms median: every
    2 ms step read as a missing frame (910 rows at 700 Hz made 1300
    frames); now every row is one frame, at the file's times and rate."""
    notes: list[str] = []
    path = write_csv(tmp_path / "ms.csv", _rounded_rows(rate, rows))
    [trial], _ = read_csv(path, MARKERS, report=notes.append)
    assert len(trial.times) == rows
    written = [float(f"{k / rate:.3f}") for k in range(rows)]
    np.testing.assert_allclose(trial.times, written)
    assert fitted_rate([trial.times]) == pytest.approx(rate, rel=0.005)
    assert notes == []


def test_rows_deleted_at_700_hz_rounded_to_the_ms_come_back_at_its_rate() -> None:
    """Ten rows deleted from 700 Hz times written to the ms: ten frames back,
    spaced at the clock's 1.43 ms, not the median's 1 ms, and no others."""
    times = np.round(np.arange(910) / 700.0, 3)
    cut = np.r_[times[:400], times[410:]]
    frames = missing_frames(cut, list(range(2, 902)), "trial 0", "x.csv")
    assert len(frames.times) == 910
    np.testing.assert_array_equal(frames.rows, np.r_[0:400, 410:910])
    np.testing.assert_allclose(
        np.diff(frames.times[399:411]), (cut[400] - cut[399]) / 11
    )


def test_missing_frames_at_1000_hz_written_to_the_ms_are_put_back() -> None:
    """1 and 2 ms steps at uneven places are missing frames, not rounding:
    three deleted rows of a 1000 Hz trial come back."""
    times = np.round(np.delete(np.arange(1300) / 1000.0, [100, 150, 900]), 3)
    frames = missing_frames(times, list(range(2, 1299)), "trial 0", "x.csv")
    np.testing.assert_allclose(frames.times, np.arange(1300) / 1000.0, atol=1e-9)


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
