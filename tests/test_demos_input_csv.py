"""CSV import refuses malformed cells naming line and column, and notes gaps."""

from __future__ import annotations

import csv
import json
import pathlib

import numpy as np
import pytest

from armplan.cli.main import main
from shared.demos import read_demos
from shared.demos.csv_import import read_csv
from shared.demos.markers import MarkerMap
from shared.errors import DemoFileError
from tests.test_demos_c3d import write_reach_c3d

MARKERS = MarkerMap(shoulder="RSHO", elbow="RELB", wrist="RWRB")
HEADER = ["time", "trial"] + [
    f"{m}_{a}" for m in ("RSHO", "RELB", "RWRB") for a in "xyz"
]


#: The elbow's bend in ``arm_rows`` [rad]: 11.5 deg, within NAO's (ElbowRoll
#: 2 to 88.5 deg), so the retargeted goal is one NAO can reach.
BEND = 0.2


def arm_rows(trial: int, n: int = 30, scale: float = 1.0) -> list[list[str]]:
    """Rows of one trial of a swinging arm (upper arm 0.3 m, forearm 0.25 m),
    the elbow bent by ``BEND``."""
    angle = np.linspace(0.0, 1.2, n) + 0.1 * trial
    shoulder = np.tile([0.1, -0.2, 1.4], (n, 1))
    down = np.stack((np.sin(angle), np.zeros(n), -np.cos(angle)), axis=1)
    fore = np.stack((np.sin(angle + BEND), np.zeros(n), -np.cos(angle + BEND)), 1)
    elbow = shoulder + 0.3 * down
    wrist = elbow + 0.25 * fore
    rows = []
    for k in range(n):
        cells = [f"{k / 100:.2f}", str(trial)]
        cells += [f"{scale * v:.6f}" for p in (shoulder, elbow, wrist) for v in p[k]]
        rows.append(cells)
    return rows


def write_csv(path: pathlib.Path, rows: list[list[str]]) -> pathlib.Path:
    """``rows`` under the header; line k + 2 of the file holds ``rows[k]``."""
    with open(path, "w", newline="") as stream:
        csv.writer(stream).writerows([HEADER, *rows])
    return path


def import_cli(path: pathlib.Path, out: pathlib.Path) -> int:
    """``armplan demos import`` of the CSV ``path`` into ``out``, with a marker
    map of its shoulder, elbow and wrist columns; its exit code."""
    markers = path.with_name("map.json")
    markers.write_text(
        json.dumps({"shoulder": "RSHO", "elbow": "RELB", "wrist": "RWRB"})
    )
    return main(
        ["demos", "import", str(path), "--markers", str(markers), "-o", str(out)]
    )


def test_a_trial_cell_too_big_for_an_integer_names_line_and_column(
    tmp_path: pathlib.Path,
) -> None:
    """'1e400' (infinite as a float) is refused, not an OverflowError."""
    rows = arm_rows(0)
    rows[5][1] = "1e400"
    path = write_csv(tmp_path / "rec.csv", rows)
    with pytest.raises(DemoFileError) as caught:
        read_csv(path, MARKERS)
    assert caught.value.message == (
        f"{path}: line 7, column 'trial' holds '1e400', which is not a trial "
        "number (a whole number from 0)"
    )


@pytest.mark.parametrize("value", ["1.5", "-1", "", "one"])
def test_a_trial_number_must_be_whole(tmp_path: pathlib.Path, value: str) -> None:
    """1.5 is not silently read as trial 1; negatives, blanks, words refused."""
    rows = arm_rows(1)
    rows[3][1] = value
    path = write_csv(tmp_path / "rec.csv", rows)
    with pytest.raises(DemoFileError, match=r"line 5, column 'trial' holds") as caught:
        read_csv(path, MARKERS)
    assert caught.value.evidence["line"] == 5


def test_whole_trial_numbers_written_as_floats_are_read(tmp_path: pathlib.Path) -> None:
    """'3.0' is trial 3 (spreadsheets write whole numbers that way)."""
    rows = arm_rows(3)
    for row in rows:
        row[1] = "3.0"
    trials, _ = read_csv(write_csv(tmp_path / "rec.csv", rows), MARKERS)
    assert [t.trial for t in trials] == [3]


def test_a_bad_number_names_the_csv_column_and_line(tmp_path: pathlib.Path) -> None:
    """The message names RSHO_z and the line, not the role 'shoulder'."""
    rows = arm_rows(0)
    rows[2][4] = "abc"
    path = write_csv(tmp_path / "rec.csv", rows)
    with pytest.raises(DemoFileError) as caught:
        read_csv(path, MARKERS)
    assert caught.value.message == (
        f"{path}: line 4, column 'RSHO_z' holds 'abc', which is not a number"
    )


def test_an_infinite_coordinate_is_refused(tmp_path: pathlib.Path) -> None:
    """'inf' is not a gap (that is an empty cell) but a bad value."""
    rows = arm_rows(0)
    rows[0][6] = "inf"
    path = write_csv(tmp_path / "rec.csv", rows)
    with pytest.raises(DemoFileError, match=r"line 2, column 'RELB_y' holds 'inf'"):
        read_csv(path, MARKERS)


def test_a_row_lacking_cells_is_refused_naming_its_line(tmp_path: pathlib.Path) -> None:
    """A row cut short is not a gap: refused, naming line and first lost column."""
    rows = arm_rows(0)
    rows[7] = rows[7][:8]
    path = write_csv(tmp_path / "rec.csv", rows)
    with pytest.raises(DemoFileError) as caught:
        read_csv(path, MARKERS)
    assert caught.value.message == (
        f"{path}: line 9 has 8 cells, the header 11: it lacks column 'RWRB_x' "
        "(leave a cell empty for a missing sample)"
    )


def test_an_empty_time_is_refused_naming_its_line(tmp_path: pathlib.Path) -> None:
    """Without its time a row cannot be placed: refused, naming the line."""
    rows = arm_rows(0)
    rows[4][0] = ""
    path = write_csv(tmp_path / "rec.csv", rows)
    with pytest.raises(DemoFileError, match="trial 0 must be given and increase: "):
        read_csv(path, MARKERS)
    with pytest.raises(DemoFileError, match="line 6 has none"):
        read_csv(path, MARKERS)


def test_empty_marker_cells_are_filled_and_the_cli_says_so(
    tmp_path: pathlib.Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """A gap of a row or two is filled from the rows around (it was dropped,
    and the trial joined across it); the import counts them on stderr."""
    rows = arm_rows(0) + arm_rows(1)
    rows[4][3] = ""
    rows[40][8] = ""
    rows[41][2] = "nan"
    path = write_csv(tmp_path / "gaps.csv", rows)
    out = tmp_path / "gaps.mcap"
    assert import_cli(path, out) == 0
    captured = capsys.readouterr()
    assert f"{out}: 1 subject, 2 trials, 60 samples" in captured.out
    notes = captured.err.splitlines()
    assert notes == [
        f"armplan: note: {path}: trial 0: filled 1 of 30 frames where a marker "
        "was missing (gaps of at most 0.1 s, by a smoothing spline), the first at "
        "frame 4 (t = 0.04 s, line 6)",
        f"armplan: note: {path}: trial 1: filled 2 of 30 frames where a marker "
        "was missing (gaps of at most 0.1 s, by a smoothing spline), the first at "
        "frame 10 (t = 0.1 s, line 42)",
    ]
    filled = read_demos(out).trials[0].wrist
    whole, _ = read_csv(write_csv(tmp_path / "whole.csv", arm_rows(0)), MARKERS)
    np.testing.assert_allclose(filled, whole[0].wrist, atol=1e-5)


def test_a_byte_order_mark_is_read_past(tmp_path: pathlib.Path) -> None:
    """Excel's "CSV UTF-8" starts with a byte-order mark: the same trials as
    without it (it was refused as lacking the column time)."""
    plain = write_csv(tmp_path / "plain.csv", arm_rows(0))
    marked = tmp_path / "marked.csv"
    marked.write_bytes(b"\xef\xbb\xbf" + plain.read_bytes())
    expected, _ = read_csv(plain, MARKERS)
    trials, _ = read_csv(marked, MARKERS)
    np.testing.assert_array_equal(trials[0].wrist, expected[0].wrist)
    np.testing.assert_array_equal(trials[0].times, expected[0].times)


def test_a_one_row_trial_is_refused_naming_the_trial_and_its_line(
    tmp_path: pathlib.Path,
) -> None:
    """A trial of one row shows no movement: the error names the trial and its
    line (it said only that fewer than two frames have all of the markers)."""
    rows = arm_rows(0) + arm_rows(1, n=1)
    path = write_csv(tmp_path / "rec.csv", rows)
    with pytest.raises(DemoFileError) as caught:
        read_csv(path, MARKERS)
    assert caught.value.message == (
        f"{path}: trial 1 has a single row (line 32); a trial needs at least 2 "
        "samples, from its start to its goal"
    )
    assert caught.value.evidence["trial"] == 1
    assert caught.value.evidence["line"] == 32


def test_a_trial_left_with_one_whole_frame_names_subject_trial_and_lines(
    tmp_path: pathlib.Path,
) -> None:
    """Three rows, two with a gap: the error names the subject, the trial and
    its lines, and says why the frames went."""
    rows = arm_rows(0) + arm_rows(1, n=3)
    rows[30][3] = ""
    rows[31][8] = ""
    path = write_csv(tmp_path / "rec.csv", rows)
    with pytest.raises(DemoFileError) as caught:
        read_csv(path, MARKERS)
    assert caught.value.message == (
        f"{path}: subject 'rec', trial 1 (lines 32-34): 1 of its 3 frames has "
        "all of the markers RSHO, RELB, RWRB (a frame with a missing marker is "
        "filled only between frames that have it); a trial needs at least 2"
    )
    assert caught.value.evidence["trial"] == 1


def test_times_in_milliseconds_are_refused_on_import(
    tmp_path: pathlib.Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """A 100 Hz trial with its times in milliseconds reads as 0.1 Hz: the
    import refuses it, naming the file, trial and lines and saying to divide
    by 1000, and writes nothing (it imported, and only the fit refused)."""
    rows = arm_rows(0)
    for k, row in enumerate(rows):
        row[0] = f"{10 * k}"
    path = write_csv(tmp_path / "ms.csv", rows)
    out = tmp_path / "ms.mcap"
    assert import_cli(path, out) == 1
    assert capsys.readouterr().err == (
        f"armplan: error: {path}: trial 0 (lines 2-31): the times step 10 apart "
        "(median), a sample rate of 0.1 Hz if they are seconds; demonstrations "
        'are sampled at 1 to 10000 Hz: these look like milliseconds: give "time_units"'
        ': "ms" in the marker map, or divide them by 1000\n'
    )
    assert not out.exists()
    with pytest.raises(DemoFileError) as caught:
        read_csv(path, MARKERS)
    assert caught.value.evidence["trial"] == 0
    assert caught.value.evidence["rate"] == pytest.approx(0.1)


def test_a_map_saying_milliseconds_reads_the_same_trial(tmp_path: pathlib.Path) -> None:
    """``"time_units": "ms"``: the times in milliseconds give the trial the
    times in seconds give, to the sample; the same map refuses seconds."""
    rows = arm_rows(0)
    seconds = write_csv(tmp_path / "s.csv", rows)
    for k, row in enumerate(rows):
        row[0] = f"{10 * k}"
    milliseconds = write_csv(tmp_path / "ms.csv", rows)
    in_ms = MARKERS.model_copy(update={"time_units": "ms"})
    [want], _ = read_csv(seconds, MARKERS)
    [got], _ = read_csv(milliseconds, in_ms)
    np.testing.assert_allclose(got.times, want.times, rtol=0, atol=1e-12)
    for part in ("shoulder", "elbow", "wrist"):
        np.testing.assert_array_equal(getattr(got, part), getattr(want, part))
    with pytest.raises(DemoFileError) as caught:
        read_csv(seconds, in_ms)
    assert "times read as ms as the marker map says" in caught.value.message
    assert caught.value.message.endswith(
        'the file\'s times look like seconds: leave "time_units": "ms" out of the '
        "marker map"
    )


def test_a_time_column_of_frame_numbers_is_refused_on_import(
    tmp_path: pathlib.Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """Times 0, 1, 2, ... read as 1 Hz: refused, naming the trial and lines
    and asking whether they are frame numbers (it imported, and the error
    then blamed the 30 s trial's stillness)."""
    rows = arm_rows(0)
    for k, row in enumerate(rows):
        row[0] = str(k)
    path = write_csv(tmp_path / "frames.csv", rows)
    out = tmp_path / "frames.mcap"
    assert import_cli(path, out) == 1
    assert capsys.readouterr().err == (
        f"armplan: error: {path}: trial 0 (lines 2-31): the times step 1 s apart "
        "(median), a sample rate of 1 Hz; motion capture samples at 20 Hz or "
        "more: are these frame numbers? Times must be in seconds (a frame's "
        "number over the capture's rate)\n"
    )
    assert not out.exists()


def test_a_c3d_file_named_csv_is_said_to_be_one(tmp_path: pathlib.Path) -> None:
    """A C3D file named .csv was "not a CSV file ('utf-8' codec can't decode
    byte 0x80 in position 14: invalid start byte)"; it is named a C3D file."""
    write_reach_c3d(tmp_path / "capture.c3d")
    path = (tmp_path / "capture.c3d").rename(tmp_path / "capture.csv")
    with pytest.raises(DemoFileError) as caught:
        read_csv(path, MARKERS)
    assert caught.value.message == (
        f"{path}: not a CSV file: it is a C3D file (binary); name it .c3d to import it"
    )


def test_a_csv_file_not_in_utf8_is_said_to_be_so(tmp_path: pathlib.Path) -> None:
    """A CSV saved as Latin-1 (a marker named Schulterä) is told to be saved
    as UTF-8, not called a C3D file."""
    path = write_csv(tmp_path / "latin.csv", arm_rows(0))
    path.write_bytes(path.read_bytes().replace(b"RSHO", "Schulterä".encode("latin-1")))
    with pytest.raises(DemoFileError) as caught:
        read_csv(path, MARKERS)
    assert caught.value.message == (
        f"{path}: not a CSV file: byte 19 is not UTF-8 text; save the CSV as "
        "UTF-8 (or it is not a CSV file)"
    )
