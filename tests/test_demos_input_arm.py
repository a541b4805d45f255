"""Import refuses degenerate and implausible arms before writing anything."""

from __future__ import annotations

import json
import pathlib

import numpy as np
import pytest

from armplan.cli.main import main
from shared.demos import DemoSet, Subject, synthesize, write_demos
from shared.demos.anthropometry import draw_subjects
from shared.demos.csv_import import read_csv
from shared.demos.importing import SEGMENT_RANGE
from shared.demos.markers import MarkerMap, read_marker_map
from shared.errors import DemoFileError
from tests.test_demos_input_csv import arm_rows, write_csv

MAP = {"shoulder": "RSHO", "elbow": "RELB", "wrist": "RWRB"}


def _import(
    tmp_path: pathlib.Path, csv_path: pathlib.Path, markers: dict[str, str]
) -> tuple[int, pathlib.Path]:
    """Run ``armplan demos import``; the exit code and the output's path."""
    map_path = tmp_path / "map.json"
    map_path.write_text(json.dumps(markers))
    out = tmp_path / "x.mcap"
    code = main(
        ["demos", "import", "--markers", str(map_path), "-o", str(out), str(csv_path)]
    )
    return code, out


def test_one_marker_for_every_role_is_refused_and_nothing_written(
    tmp_path: pathlib.Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """The map giving RSHO for shoulder, elbow and wrist: a typed error, no file."""
    path = write_csv(tmp_path / "mocap.csv", arm_rows(0))
    same = {"shoulder": "RSHO", "elbow": "RSHO", "wrist": "RSHO"}
    code, out = _import(tmp_path, path, same)
    assert code == 1
    assert capsys.readouterr().err == (
        f"armplan: error: {tmp_path / 'map.json'}: the marker map gives marker "
        "'RSHO' for shoulder, elbow and wrist: each needs its own marker, else "
        "the arm has a zero-length segment\n"
    )
    assert not out.exists()


def test_coinciding_markers_name_subject_trial_and_frame(
    tmp_path: pathlib.Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """Elbow and wrist recorded at one place in one frame: a degenerate forearm."""
    rows = arm_rows(0)
    rows[3][8:11] = rows[3][5:8]
    path = write_csv(tmp_path / "mocap.csv", rows)
    code, out = _import(tmp_path, path, MAP)
    assert code == 1
    assert capsys.readouterr().err == (
        f"armplan: error: {path}: subject 'mocap', trial 0, frame 3 (t = 0.03 s, "
        "line 5): degenerate arm, zero-length forearm ('RELB' to 'RWRB'): the "
        "markers coincide\n"
    )
    assert not out.exists()


def test_a_map_in_mm_on_data_in_metres_is_refused_with_a_units_hint(
    tmp_path: pathlib.Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """A 0.3 mm upper arm names the length found and the units declared."""
    rows = arm_rows(0)
    path = write_csv(tmp_path / "mocap.csv", rows)
    code, out = _import(tmp_path, path, {**MAP, "units": "mm"})
    assert code == 1
    lines = f"lines 2-{len(rows) + 1}"  # line k + 2 holds rows[k]
    assert capsys.readouterr().err == (
        f"armplan: error: {path}: subject 'mocap', trial 0 ({lines}): the upper "
        "arm ('RSHO' to 'RELB') is 0.3 mm long (median of 30 frames), but a "
        "human's is 5 cm to 1 m; coordinates were read in mm, as the marker "
        'map\'s "units" '
        "declares: are the units right?\n"
    )
    assert not out.exists()


def test_data_in_cm_read_as_metres_is_refused(tmp_path: pathlib.Path) -> None:
    """Without "units" a CSV is in metres: a 30 m upper arm says so."""
    path = write_csv(tmp_path / "mocap.csv", arm_rows(0, scale=100.0))
    with pytest.raises(DemoFileError) as caught:
        read_csv(path, MarkerMap.model_validate(MAP))
    assert "is 30 m long" in caught.value.message
    assert 'read in m, the file\'s default (the marker map has no "units")' in (
        caught.value.message
    )
    assert caught.value.evidence["segment"] == "upper arm"


def test_a_shoulder_misplaced_in_one_frame_is_refused(
    tmp_path: pathlib.Path,
) -> None:
    """A shoulder x 0.6 m off in one frame: a 0.528 m upper arm among 0.3 m ones."""
    rows = arm_rows(0)
    rows[12][2] = "0.700000"
    path = write_csv(tmp_path / "mocap.csv", rows)
    with pytest.raises(DemoFileError) as caught:
        read_csv(path, MarkerMap.model_validate(MAP))
    assert caught.value.message == (
        f"{path}: subject 'mocap', trial 0, frame 12 (t = 0.12 s, line 14): the "
        "upper arm ('RSHO' to 'RELB') is 0.528 m long, its median 0.3 m (a "
        "human's is 5 cm to 1 m): a marker is misplaced or mislabelled there "
        "(empty cells would have it filled from the frames around, for a gap of "
        "a few frames)"
    )


def test_a_shoulder_column_scaled_by_a_million_is_refused(
    tmp_path: pathlib.Path,
) -> None:
    """Every shoulder x times 1e6: far off in every frame, so the units are named."""
    rows = arm_rows(0)
    for row in rows:
        row[2] = f"{float(row[2]) * 1e6:g}"
    path = write_csv(tmp_path / "mocap.csv", rows)
    with pytest.raises(DemoFileError) as caught:
        read_csv(path, MarkerMap.model_validate(MAP))
    message = caught.value.message
    assert message.startswith(
        f"{path}: subject 'mocap', trial 0 (lines 2-{len(rows) + 1}): marker "
        "'RSHO' at frame 0 is at "
    )
    assert message.endswith(
        "not a position (line 2); so are most of its frames: coordinates were "
        'read in m, the file\'s default (the marker map has no "units"): are '
        "the units right?"
    )


def test_the_range_holds_every_synthetic_subject() -> None:
    """The plausible range is generous: drawn subjects lie well inside it."""
    low, high = SEGMENT_RANGE
    for seed in range(20):
        for subject in draw_subjects(16, np.random.default_rng(seed)):
            assert 2 * low < subject.forearm < subject.upper_arm < high / 2


def test_the_marker_map_reader_refuses_a_shared_thumb(tmp_path: pathlib.Path) -> None:
    """The thumb-side marker cannot be the wrist's own."""
    path = tmp_path / "map.json"
    path.write_text(json.dumps({**MAP, "thumb": "RWRB"}))
    with pytest.raises(DemoFileError, match="'RWRB' for wrist and thumb"):
        read_marker_map(path)


def test_a_capture_given_as_the_marker_map_is_a_clear_error(
    tmp_path: pathlib.Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """The C3D file given to --markers too (arguments swapped) ended the
    import with a UnicodeDecodeError traceback; now exit 1 naming the map,
    nothing written."""
    from tests.test_demos_c3d import write_reach_c3d

    capture = tmp_path / "reach.c3d"
    write_reach_c3d(capture)
    out = tmp_path / "x.mcap"
    argv = ["demos", "import", str(capture), "--markers", str(capture)]
    assert main([*argv, "-o", str(out)]) == 1
    err = capsys.readouterr().err
    assert f"{capture}: the marker map is not JSON text (byte " in err
    assert not out.exists()


def test_the_marker_maps_arm_is_read_in_any_case(tmp_path: pathlib.Path) -> None:
    """ "Left" was refused ('Input should be right or left') while --arm takes
    any case; a name that is no arm is still refused, saying which are."""
    path = tmp_path / "map.json"
    path.write_text(json.dumps({**MAP, "arm": "Left"}))
    assert read_marker_map(path).arm == "left"
    path.write_text(json.dumps({**MAP, "arm": "middle"}))
    with pytest.raises(DemoFileError, match="unknown arm 'middle'"):
        read_marker_map(path)


def test_write_demos_leaves_no_file_when_a_subject_is_invalid(
    tmp_path: pathlib.Path,
) -> None:
    """A zero forearm is a typed error; an older file of that name is kept."""
    out = tmp_path / "x.mcap"
    out.write_bytes(b"older")
    demos = synthesize(0, subjects=1, trials=1)
    bad = DemoSet({"S01": Subject("S01", 1.7, 0.3, 0.0)}, demos.trials)
    with pytest.raises(DemoFileError, match="subject 'S01': invalid DemoSubject"):
        write_demos(out, bad)
    assert out.read_bytes() == b"older"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["x.mcap"]
