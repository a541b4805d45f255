"""Each refusal of one CSV trial names the file's lines of the offending rows.

The file has blank lines (before and after the header, among the rows) and
a quoted cell over two lines, so a row's line is not its index plus two:
each test computes the expected line from where the bad row was written.
"""

from __future__ import annotations

import csv
import io
import json
import pathlib

import pytest

from armplan.cli.commands.demos import _check_one_reach
from armplan.cli.main import main
from shared.demos.csv_import import read_csv
from shared.demos.markers import MarkerMap
from shared.errors import DemoFileError
from tests.test_demos_input_csv import HEADER, arm_rows
from tests.test_demos_one_reach import _held, _still
from tests.test_demos_reach_pause import _two_moves

MARKERS = MarkerMap(shoulder="RSHO", elbow="RELB", wrist="RWRB")
THUMBED = MARKERS.model_copy(update={"thumb": "RWRA"})
MAP = {"shoulder": "RSHO", "elbow": "RELB", "wrist": "RWRB"}


def _text(cells: list[str]) -> str:
    stream = io.StringIO()
    csv.writer(stream, lineterminator="\n").writerow(cells)
    return stream.getvalue()


def write_spaced(
    path: pathlib.Path, rows: list[list[str]], header: list[str] = HEADER
) -> list[int]:
    """Write ``rows`` under ``header`` with blank lines and a two-line cell.

    Returns:
        Each row's line in the file (from 1), counted as it is written.
    """
    chunks = ["\n", _text([*header, "note"]), "\n"]
    lines = []
    for k, row in enumerate(rows):
        if k % 7 == 3:
            chunks.append("\n")
        lines.append(1 + sum(chunk.count("\n") for chunk in chunks))
        chunks.append(_text([*row, "two\nlines" if k == 1 else ""]))
    path.write_text("".join(chunks))
    return lines


def _refusal(path: pathlib.Path, markers: MarkerMap = MARKERS) -> DemoFileError:
    with pytest.raises(DemoFileError) as caught:
        read_csv(path, markers)
    return caught.value


def _two_trials() -> list[list[str]]:
    """Trials 0 and 1, 30 rows each at 100 Hz: trial 1's rows are 30..59."""
    return arm_rows(0) + arm_rows(1)


def test_rows_map_to_their_lines_past_blank_lines_and_a_two_line_cell(
    tmp_path: pathlib.Path,
) -> None:
    """The lines the file was written with are the trial's lines."""
    path = tmp_path / "rec.csv"
    lines = write_spaced(path, _two_trials())
    trials, _ = read_csv(path, MARKERS)
    assert trials[0].lines == lines[:30]
    assert trials[1].lines == lines[30:]
    assert lines[2] == lines[1] + 2  # the cell over two lines


@pytest.mark.parametrize(("time", "why"), [("", "none"), ("0.09", "t = 0.09 s")])
def test_a_missing_or_repeated_time_names_its_line(
    tmp_path: pathlib.Path, time: str, why: str
) -> None:
    """Trial 1's row 10 without a time, or repeating row 9's."""
    rows = _two_trials()
    rows[40][0] = time
    path = tmp_path / "rec.csv"
    lines = write_spaced(path, rows)
    error = _refusal(path)
    assert f"the times of trial 1 must be given and increase: line {lines[40]} " in (
        error.message
    )
    assert why in error.message
    assert error.evidence["line"] == lines[40]
    assert error.evidence["trial"] == 1


def test_a_time_going_back_names_both_lines(tmp_path: pathlib.Path) -> None:
    rows = _two_trials()
    rows[40][0] = "0.05"
    path = tmp_path / "rec.csv"
    lines = write_spaced(path, rows)
    error = _refusal(path)
    assert error.reason == (
        f"the times of trial 1 must be given and increase: line {lines[40]} has "
        f"t = 0.05 s, line {lines[39]} t = 0.09 s"
    )
    assert error.evidence["previous_line"] == lines[39]


def test_a_single_row_trial_names_its_line(tmp_path: pathlib.Path) -> None:
    path = tmp_path / "rec.csv"
    lines = write_spaced(path, arm_rows(0) + arm_rows(1, n=1))
    error = _refusal(path)
    assert f"trial 1 has a single row (line {lines[30]})" in error.message
    assert error.evidence["line"] == lines[30]


def test_times_in_frame_numbers_name_the_trials_lines(tmp_path: pathlib.Path) -> None:
    rows = _two_trials()
    for k, row in enumerate(rows[30:]):
        row[0] = str(k)
    path = tmp_path / "rec.csv"
    lines = write_spaced(path, rows)
    error = _refusal(path)
    assert error.reason.startswith(f"trial 1 (lines {lines[30]}-{lines[59]}): ")
    assert (error.evidence["line"], error.evidence["last_line"]) == (
        lines[30],
        lines[59],
    )


def test_rows_left_out_name_the_lines_around(tmp_path: pathlib.Path) -> None:
    """Trial 1's rows of 0.08-0.22 s left out: the rows around the hole are named."""
    rows = _two_trials()
    rows = rows[:38] + rows[53:]
    path = tmp_path / "rec.csv"
    lines = write_spaced(path, rows)
    error = _refusal(path)
    assert (
        f"trial 1: no rows between line {lines[37]} (t = 0.07 s) and line "
        f"{lines[38]} (t = 0.23 s)"
    ) in error.message
    assert (error.evidence["first_line"], error.evidence["line"]) == (
        lines[37],
        lines[38],
    )


def test_a_marker_far_off_names_trial_and_line(tmp_path: pathlib.Path) -> None:
    rows = _two_trials()
    rows[45][2] = "1e6"
    path = tmp_path / "rec.csv"
    lines = write_spaced(path, rows)
    error = _refusal(path)
    assert error.reason.startswith(
        f"subject 'rec', trial 1 (lines {lines[30]}-{lines[59]}): marker 'RSHO' "
        "at frame 15 is at "
    )
    assert error.reason.endswith(f"not a position (line {lines[45]})")
    assert error.evidence["line"] == lines[45]


def test_too_few_whole_frames_name_the_trials_lines(tmp_path: pathlib.Path) -> None:
    rows = arm_rows(0) + arm_rows(1, n=3)
    rows[30][3], rows[31][8] = "", ""
    path = tmp_path / "rec.csv"
    lines = write_spaced(path, rows)
    error = _refusal(path)
    assert f"trial 1 (lines {lines[30]}-{lines[32]}): 1 of its 3 frames" in (
        error.message
    )
    assert (error.evidence["first_line"], error.evidence["last_line"]) == (
        lines[30],
        lines[32],
    )


@pytest.mark.parametrize(("first", "last"), [(35, 50), (57, 59)])
def test_a_marker_gap_names_its_lines(
    tmp_path: pathlib.Path, first: int, last: int
) -> None:
    """0.16 s of a missing shoulder, or one at trial 1's end."""
    rows = _two_trials()
    for row in rows[first : last + 1]:
        row[2] = ""
    path = tmp_path / "rec.csv"
    lines = write_spaced(path, rows)
    error = _refusal(path)
    assert f"line {lines[first]}) to frame" in error.message
    assert f"line {lines[last]})" in error.message
    assert (error.evidence["first_line"], error.evidence["last_line"]) == (
        lines[first],
        lines[last],
    )


@pytest.mark.parametrize("move", [0.0, 0.2], ids=["degenerate", "misplaced"])
def test_a_bad_segment_in_one_row_names_its_line(
    tmp_path: pathlib.Path, move: float
) -> None:
    """The elbow on the shoulder, or 0.2 m off, in trial 1's row 15."""
    rows = _two_trials()
    shoulder = [float(v) for v in rows[45][2:5]]
    rows[45][5:8] = [f"{v + move:.6f}" for v in shoulder]
    path = tmp_path / "rec.csv"
    lines = write_spaced(path, rows)
    error = _refusal(path)
    assert f"trial 1, frame 15 (t = 0.15 s, line {lines[45]}): " in error.message
    assert error.evidence["line"] == lines[45]


def test_an_arm_in_wrong_units_names_the_trials_lines(tmp_path: pathlib.Path) -> None:
    """Trial 1 in kilometres: its median upper arm is 0.3 mm."""
    rows = arm_rows(0) + arm_rows(1, scale=0.001)
    path = tmp_path / "rec.csv"
    lines = write_spaced(path, rows)
    error = _refusal(path)
    assert error.reason.startswith(
        f"subject 'rec', trial 1 (lines {lines[30]}-{lines[59]}): the upper arm "
    )
    assert (error.evidence["first_line"], error.evidence["last_line"]) == (
        lines[30],
        lines[59],
    )


def test_a_thumb_marker_on_the_wrist_names_its_line(tmp_path: pathlib.Path) -> None:
    """The thumb-side marker 4 cm across the forearm (y), but on the wrist
    marker in trial 1's row 12."""
    rows = _two_trials()
    for row in rows:
        x, y, z = (float(v) for v in row[8:11])
        row += [f"{x:.6f}", f"{y + 0.04:.6f}", f"{z:.6f}"]
    rows[42][11:14] = rows[42][8:11]
    header = [*HEADER, "RWRA_x", "RWRA_y", "RWRA_z"]
    path = tmp_path / "rec.csv"
    lines = write_spaced(path, rows, header)
    error = _refusal(path, THUMBED)
    assert f"trial 1 (lines {lines[30]}-{lines[59]}), frame 12 (t = 0.12 s, line " in (
        error.message
    )
    assert f"line {lines[42]}): the thumb-side marker 'RWRA' is 0.0 mm" in (
        error.message
    )
    assert error.evidence["line"] == lines[42]


def _not_one_reach(
    tmp_path: pathlib.Path, rows: list[list[str]], capsys: pytest.CaptureFixture[str]
) -> tuple[str, DemoFileError, list[int]]:
    """``armplan demos import``'s error for trial 1 (rows 30 on) of
    ``arm_rows(0) + rows``, its ``DemoFileError`` and the rows' lines."""
    rows = arm_rows(0) + [[row[0], "1", *row[2:]] for row in rows]
    path = tmp_path / "rec.csv"
    lines = write_spaced(path, rows)
    (tmp_path / "map.json").write_text(json.dumps(MAP))
    argv = ["demos", "import", str(path), "--markers", str(tmp_path / "map.json")]
    assert main([*argv, "-o", str(tmp_path / "out.mcap")]) == 1
    trials, _ = read_csv(path, MARKERS)
    with pytest.raises(DemoFileError) as caught:
        _check_one_reach(trials[1], str(path), allow=False)
    assert (
        caught.value.evidence["first_line"],
        caught.value.evidence["last_line"],
    ) == (
        lines[30],
        lines[-1],
    )
    return capsys.readouterr().err, caught.value, lines


def test_a_still_take_names_the_trials_lines(
    tmp_path: pathlib.Path, capsys: pytest.CaptureFixture[str]
) -> None:
    err, _, lines = _not_one_reach(tmp_path, _still(1.0), capsys)
    assert f"trial 1 of subject 'rec' (lines {lines[30]}-{lines[-1]}) lasts" in err


def test_a_brief_move_names_its_lines(
    tmp_path: pathlib.Path, capsys: pytest.CaptureFixture[str]
) -> None:
    err, _, lines = _not_one_reach(tmp_path, arm_rows(1, n=3), capsys)
    assert (
        f"(lines {lines[30]}-{lines[32]}) lasts 0.02 s, and its wrist moves for "
        f"0.01 s (from 0.01 s (line {lines[31]}) to 0.02 s (line {lines[32]}))"
    ) in err


def test_a_long_hold_names_its_lines(
    tmp_path: pathlib.Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """Trial 1 swings in its rows 0..29 and holds for 3.5 s after."""
    err, _, lines = _not_one_reach(tmp_path, _held(3.5), capsys)
    assert (
        f"still for 3.5 s at its goal, lines {lines[59]}-{lines[-1]} (at most 3 s; "
        f"the wrist moves from 0.01 s (line {lines[31]}) to 0.29 s (line "
        f"{lines[59]}))"
    ) in err


def test_a_stop_on_the_way_names_its_lines(
    tmp_path: pathlib.Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """Two moves 0.8 s apart: the wrist stops at 0.81 s, restarts at 1.79 s."""
    moves = _two_moves(0.8)
    err, _, lines = _not_one_reach(tmp_path, moves, capsys)
    times = [row[0] for row in moves]
    stops, restarts = lines[30 + times.index("0.81")], lines[30 + times.index("1.79")]
    assert f"from 0.81 s (line {stops}) to 1.79 s (line {restarts})" in err
    assert f"stops (0.81 s, line {stops}) and restarts (1.79 s, line {restarts})" in err


def test_a_trial_of_many_reaches_names_its_lines(
    tmp_path: pathlib.Path, capsys: pytest.CaptureFixture[str]
) -> None:
    err, _, lines = _not_one_reach(tmp_path, arm_rows(1, n=1100), capsys)
    assert f"(lines {lines[30]}-{lines[-1]}) lasts 11.0 s, far longer" in err
