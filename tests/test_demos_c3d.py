"""C3D import: real files written with ezc3d, read back, retargeted to NAO."""

from __future__ import annotations

import json
import pathlib
import re
import subprocess
import sys
from typing import NamedTuple

import ezc3d
import numpy as np
import pytest

from shared.demos import nao_arm_size, read_demos
from shared.demos.anthropometry import subject_from_stature
from shared.demos.c3d_import import read_c3d
from shared.demos.grid import grid_targets
from shared.demos.markers import MarkerMap, read_marker_map
from shared.demos.reach_model import AVERAGE_STYLE, plan_reach, sample_reach
from shared.demos.retarget import ArmTrack, retarget
from shared.errors import DemoFileError

#: The lab's shoulder [mm], in a Y-up lab whose -z is the subject's forward.
LAB_SHOULDER = np.array([250.0, 1400.0, -300.0])
MAP = {
    "shoulder": "RSHO",
    "elbow": "RELB",
    "wrist": "RWRB",
    "thumb": "RWRA",
    "axes": ["-z", "-x", "y"],
    "subject": "P01",
}


class Recorded(NamedTuple):
    """A human reach in the subject's torso axes [m]."""

    elbow: np.ndarray
    wrist: np.ndarray
    thumb: np.ndarray
    frame: np.ndarray
    upper: float
    forearm: float


def _reach() -> Recorded:
    person = subject_from_stature("P01", 1.74)
    target = grid_targets(person.arm_length)[13]
    reach = sample_reach(plan_reach(person, AVERAGE_STYLE, target), person, 100.0)
    thumb = reach.wrist + 0.02 * reach.wrist_frame[:, :, 2]
    return Recorded(
        reach.elbow,
        reach.wrist,
        thumb,
        reach.wrist_frame,
        person.upper_arm,
        person.forearm,
    )


def _to_lab(points: np.ndarray) -> np.ndarray:
    """Torso axes (forward, left, up) [m] to the lab's (x, y, z) [mm]."""
    forward, left, up = points[:, 0], points[:, 1], points[:, 2]
    return LAB_SHOULDER + 1000.0 * np.stack((-left, up, -forward), axis=1)


def _write_c3d(
    path: pathlib.Path, markers: dict[str, np.ndarray], rate: float = 100.0
) -> None:
    _write_points(path, list(markers), list(markers.values()), rate)


def _write_points(
    path: pathlib.Path,
    labels: list[str],
    tracks: list[np.ndarray],
    rate: float = 100.0,
) -> None:
    """A C3D file of points ``labels`` [mm], each track of shape (frames, 3)."""
    c3d = ezc3d.c3d()
    c3d["parameters"]["POINT"]["RATE"]["value"] = [rate]
    c3d["parameters"]["POINT"]["LABELS"]["value"] = tuple(labels)
    c3d["parameters"]["POINT"]["UNITS"]["value"] = ["mm"]
    cloud = np.ones((4, len(labels), len(tracks[0])))
    for i, points in enumerate(tracks):
        cloud[:3, i, :] = points.T
    c3d["data"]["points"] = cloud
    c3d.write(str(path))


def write_reach_c3d(path: pathlib.Path) -> None:
    """A reach of four markers, RSHO RELB RWRB RWRA, as ``MAP`` maps them."""
    reach = _reach()
    zeros = np.zeros_like(reach.wrist)
    points = (zeros, reach.elbow, reach.wrist, reach.thumb)
    _write_c3d(path, {n: _to_lab(p) for n, p in zip(MAP_NAMES, points, strict=True)})


#: The marker names ``MAP`` gives, shoulder to thumb.
MAP_NAMES = ("RSHO", "RELB", "RWRB", "RWRA")


@pytest.fixture(scope="module")
def recorded() -> Recorded:
    return _reach()


@pytest.fixture
def c3d_file(tmp_path: pathlib.Path, recorded: Recorded) -> pathlib.Path:
    path = tmp_path / "reach.c3d"
    zeros = np.zeros_like(recorded.wrist)
    _write_c3d(
        path,
        {
            "Sub:RSHO": _to_lab(zeros),
            "Sub:RELB": _to_lab(recorded.elbow),
            "Sub:RWRB": _to_lab(recorded.wrist),
            "Sub:RWRA": _to_lab(recorded.thumb),
            "Sub:HEAD": _to_lab(zeros + np.array([0.0, 0.2, 0.3])),
        },
    )
    return path


def test_c3d_import_retargets_the_recorded_arm(
    c3d_file: pathlib.Path, recorded: Recorded
) -> None:
    """Units, axes, prefixes handled; NAO keeps the human segment directions."""
    trial, person = read_c3d(c3d_file, MarkerMap.model_validate(MAP))
    zeros = np.zeros_like(recorded.wrist)
    expected = retarget(
        ArmTrack(zeros, recorded.elbow, recorded.wrist), nao_arm_size("right")
    )
    np.testing.assert_allclose(trial.elbow, expected.elbow, atol=1e-6)
    np.testing.assert_allclose(trial.wrist, expected.wrist, atol=1e-6)
    np.testing.assert_allclose(trial.times, np.arange(len(trial.times)) / 100.0)
    np.testing.assert_allclose(trial.target, expected.wrist[-1], atol=1e-6)
    assert person.name == "P01"
    assert person.upper_arm == pytest.approx(recorded.upper, abs=1e-5)
    assert person.forearm == pytest.approx(recorded.forearm, abs=1e-5)
    assert trial.wrist_frame is not None
    np.testing.assert_allclose(trial.wrist_frame, recorded.frame, atol=1e-4)


def test_missing_markers_are_named(c3d_file: pathlib.Path) -> None:
    """A C3D without the mapped markers: the error names them and lists the file's."""
    markers = MarkerMap.model_validate({**MAP, "elbow": "LELB", "wrist": "LWRB"})
    with pytest.raises(DemoFileError, match="lacks the mapped markers") as caught:
        read_c3d(c3d_file, markers)
    message = caught.value.message
    assert "elbow 'LELB'" in message and "wrist 'LWRB'" in message
    assert "Sub:RELB" in message


def test_two_people_in_one_capture_need_the_full_label(
    tmp_path: pathlib.Path, recorded: Recorded
) -> None:
    """Sub:RSHO and Sub2:RSHO both end in the mapped RSHO: ambiguous, naming
    both and the full label to map (which imports); it used to say the file
    lacks RSHO, which it has twice."""
    path = tmp_path / "two.c3d"
    zeros = np.zeros_like(recorded.wrist)
    arm = {
        "RSHO": _to_lab(zeros),
        "RELB": _to_lab(recorded.elbow),
        "RWRB": _to_lab(recorded.wrist),
    }
    _write_c3d(
        path,
        {f"{who}:{name}": p + shift for who, shift in (("Sub", 0), ("Sub2", 900))
         for name, p in arm.items()},
    )  # fmt: skip
    plain = {k: v for k, v in MAP.items() if k != "thumb"}
    with pytest.raises(DemoFileError) as caught:
        read_c3d(path, MarkerMap.model_validate(plain))
    assert caught.value.message == (
        f"{path}: the mapped marker shoulder 'RSHO' is ambiguous: the C3D file "
        "has Sub:RSHO, Sub2:RSHO (one per subject); map the one to import by its "
        'full label, e.g. "shoulder": "Sub:RSHO"'
    )
    full = {**plain, "shoulder": "Sub:RSHO", "elbow": "Sub:RELB", "wrist": "Sub:RWRB"}
    trial, _ = read_c3d(path, MarkerMap.model_validate(full))
    expected = retarget(
        ArmTrack(zeros, recorded.elbow, recorded.wrist), nao_arm_size("right")
    )
    np.testing.assert_allclose(trial.wrist, expected.wrist, atol=1e-6)


def test_labels_past_the_255th_are_read(
    tmp_path: pathlib.Path, c3d_file: pathlib.Path
) -> None:
    """A capture of over 255 points continues its labels in POINT:LABELS2:
    the arm's markers there were said to be missing. Read, they import as
    the same markers alone do."""
    alone = read_c3d(c3d_file, MarkerMap.model_validate(MAP))[0]
    arm = ezc3d.c3d(str(c3d_file))
    frames = arm["data"]["points"].shape[2]
    labels = [f"*{i}" for i in range(260)] + list(
        arm["parameters"]["POINT"]["LABELS"]["value"]
    )
    tracks = [np.full((frames, 3), 100.0 + i) for i in range(260)]
    tracks += list(np.moveaxis(arm["data"]["points"][:3], 0, 2))
    path = tmp_path / "many.c3d"
    _write_points(path, labels, tracks)
    assert "LABELS2" in ezc3d.c3d(str(path))["parameters"]["POINT"]
    trial = read_c3d(path, MarkerMap.model_validate(MAP))[0]
    np.testing.assert_allclose(trial.wrist, alone.wrist)
    np.testing.assert_allclose(trial.elbow, alone.elbow)


def test_a_mapped_label_on_two_points_is_refused(
    tmp_path: pathlib.Path, recorded: Recorded
) -> None:
    """Two points labelled RSHO, the first never seen: the first was taken,
    and the import said "0 of 100 frames have all markers". Refused, naming
    the label and its points."""
    zeros = np.zeros_like(recorded.wrist)
    tracks = [_to_lab(p) for p in (zeros, recorded.elbow, recorded.wrist, zeros)]
    tracks[0][:] = np.nan
    path = tmp_path / "twice.c3d"
    _write_points(path, ["Sub:RSHO", "RELB", "RWRB", "RSHO"], tracks)
    plain = MarkerMap.model_validate({k: v for k, v in MAP.items() if k != "thumb"})
    read_c3d(path, plain)  # an exact label is taken over a prefixed one
    _write_points(path, ["RSHO", "RELB", "RWRB", "RSHO"], tracks)
    with pytest.raises(DemoFileError) as caught:
        read_c3d(path, plain)
    assert caught.value.message == (
        f"{path}: the mapped marker shoulder 'RSHO' is the label of 2 points of "
        "the C3D file (points 1, 4), so which one is the shoulder is unknown; "
        "give the others other labels in the capture software and export again"
    )


def test_a_frame_with_a_gap_is_filled(
    tmp_path: pathlib.Path, recorded: Recorded
) -> None:
    """A frame where a marker is missing (NaN) is filled from the frames
    around (it was left out, and the trial joined across the gap)."""
    wrist = _to_lab(recorded.wrist)
    wrist[10] = np.nan
    path = tmp_path / "gap.c3d"
    _write_c3d(
        path,
        {
            "RSHO": _to_lab(np.zeros_like(recorded.wrist)),
            "RELB": _to_lab(recorded.elbow),
            "RWRB": wrist,
        },
    )
    markers = MarkerMap.model_validate({k: v for k, v in MAP.items() if k != "thumb"})
    trial, _ = read_c3d(path, markers)
    assert len(trial.times) == len(recorded.wrist)
    zeros = np.zeros_like(recorded.wrist)
    expected = retarget(
        ArmTrack(zeros, recorded.elbow, recorded.wrist), nao_arm_size("right")
    )
    np.testing.assert_allclose(trial.wrist, expected.wrist, atol=1e-5)
    assert trial.wrist_frame is None


def test_a_truncated_c3d_file_is_refused(
    c3d_file: pathlib.Path, tmp_path: pathlib.Path
) -> None:
    """Cut in half, ezc3d reads a third of the frames without complaint (and
    shortens its header to match): refused naming both counts, not imported
    as a shorter trial whose last frame is mid-reach."""
    whole = c3d_file.read_bytes()
    cut = tmp_path / "cut.c3d"
    cut.write_bytes(whole[: len(whole) // 2])
    frames = len(read_c3d(c3d_file, MarkerMap.model_validate(MAP))[0].times)
    with pytest.raises(DemoFileError, match=rf"truncated: its header says {frames} "):
        read_c3d(cut, MarkerMap.model_validate(MAP))


@pytest.mark.parametrize(
    ("count", "parameter", "value"),
    [
        ("at least 69994", None, None),  # the last block's padding not counted
        ("70000", ("TRIAL", "ACTUAL_START_FIELD"), [1, 0]),
        ("70000", ("POINT", "LONG_FRAMES"), [70000.0]),
    ],
)
def test_a_capture_longer_than_a_c3d_header_counts_is_refused(
    tmp_path: pathlib.Path,
    recorded: Recorded,
    count: str,
    parameter: tuple[str, str] | None,
    value: list[float] | None,
) -> None:
    """70 s at 1 kHz, the reach at its end: ezc3d reads the header's 65,535
    frames, and the import used to keep them, reach lost, without a word.
    Refused, with the count from the file's size or its long-count
    parameters (TRIAL:ACTUAL_END_FIELD is two 16-bit words, low first)."""
    frames = 70_000
    zeros = np.zeros((frames, 3))

    def padded(points: np.ndarray) -> np.ndarray:
        return np.vstack([np.repeat(points[:1], frames - len(points), 0), points])

    c3d = ezc3d.c3d()
    c3d["parameters"]["POINT"]["RATE"]["value"] = [1000.0]
    c3d["parameters"]["POINT"]["LABELS"]["value"] = ("RSHO", "RELB", "RWRB")
    c3d["parameters"]["POINT"]["UNITS"]["value"] = ["mm"]
    cloud = np.ones((4, 3, frames))
    for i, points in enumerate((zeros, padded(recorded.elbow), padded(recorded.wrist))):
        cloud[:3, i, :] = _to_lab(points).T
    c3d["data"]["points"] = cloud
    if parameter is not None:
        c3d.add_parameter(*parameter, value)
        if parameter[0] == "TRIAL":
            c3d.add_parameter(
                "TRIAL", "ACTUAL_END_FIELD", [frames & 0xFFFF, frames >> 16]
            )
    path = tmp_path / "long.c3d"
    c3d.write(str(path))
    plain = {k: v for k, v in MAP.items() if k != "thumb"}
    with pytest.raises(DemoFileError) as caught:
        read_c3d(path, MarkerMap.model_validate(plain))
    assert caught.value.message == (
        f"{path}: holds {count} frames (70.0 s at 1000 Hz), more than the 65535 "
        "a C3D header counts: only the first 65535 (65.5 s) can be read, cutting "
        "the trial short of its end. A trial is one reach, a second or two: crop "
        "the capture to the reach and export it again"
    )


@pytest.mark.parametrize("rate", [0.5, 1e6])
def test_a_point_rate_no_capture_uses_is_refused(
    tmp_path: pathlib.Path, recorded: Recorded, rate: float
) -> None:
    """At 0.5 Hz the one-second reach read as 198 s long, at 1 MHz as 0.1 ms;
    both were imported, and only the fit refused them."""
    path = tmp_path / "rate.c3d"
    zeros = np.zeros_like(recorded.wrist)
    markers = {
        "Sub:RSHO": _to_lab(zeros),
        "Sub:RELB": _to_lab(recorded.elbow),
        "Sub:RWRB": _to_lab(recorded.wrist),
        "Sub:RWRA": _to_lab(recorded.thumb),
    }
    _write_c3d(path, markers, rate)
    with pytest.raises(
        DemoFileError, match=re.escape(f"its point rate is {rate:g} Hz")
    ):
        read_c3d(path, MarkerMap.model_validate(MAP))


def test_a_header_rate_below_any_capture_is_refused(
    tmp_path: pathlib.Path, recorded: Recorded
) -> None:
    """A 100 Hz reach whose header says 10 Hz was imported as a 6.7 s reach
    without a word (a CSV at 10 Hz is refused); now refused naming the
    rate, as for a CSV."""
    path = tmp_path / "rate.c3d"
    zeros = np.zeros_like(recorded.wrist)
    points = (zeros, recorded.elbow, recorded.wrist, recorded.thumb)
    _write_c3d(
        path, {n: _to_lab(p) for n, p in zip(MAP_NAMES, points, strict=True)}, 10.0
    )
    with pytest.raises(DemoFileError) as caught:
        read_c3d(path, MarkerMap.model_validate(MAP))
    assert caught.value.message == (
        f"{path}: its point rate is 10 Hz; motion capture samples at 20 Hz or "
        "more: is the header's rate right? (a CSV sampled below it is refused too)"
    )


def test_two_people_under_one_subject_name_are_refused(
    tmp_path: pathlib.Path, c3d_file: pathlib.Path, recorded: Recorded
) -> None:
    """The same map's subject for two files whose arms differ by 30 %: two
    people under one name, refused naming the file; the same person in two
    files is one subject; a copy of a file is one recording twice, refused."""
    bigger = tmp_path / "bigger.c3d"
    zeros = np.zeros_like(recorded.wrist)
    _write_c3d(
        bigger,
        {
            "RSHO": _to_lab(zeros),
            "RELB": _to_lab(1.3 * recorded.elbow),
            "RWRB": _to_lab(1.3 * recorded.wrist),
        },
    )
    markers = tmp_path / "map.json"
    markers.write_text(json.dumps({k: v for k, v in MAP.items() if k != "thumb"}))

    def run(*files: pathlib.Path) -> subprocess.CompletedProcess[str]:
        out = tmp_path / f"out{len(list(tmp_path.glob('out*')))}.mcap"
        command = [sys.executable, "-m", "armplan", "demos", "import", *map(str, files)]
        return subprocess.run(
            [*command, "--markers", str(markers), "-o", str(out)],
            capture_output=True,
            text=True,
            timeout=120,
            check=False,
        )

    refused = run(c3d_file, bigger)
    assert refused.returncode == 1
    assert f"{bigger}: subject 'P01' measures" in refused.stderr
    assert "two people under one name?" in refused.stderr
    back = tmp_path / "back.c3d"  # the same arm, 2 % longer, reaching back
    _write_c3d(
        back,
        {
            "RSHO": _to_lab(zeros),
            "RELB": _to_lab(1.02 * recorded.elbow[::-1]),
            "RWRB": _to_lab(1.02 * recorded.wrist[::-1]),
        },
    )
    assert run(c3d_file, back).returncode == 0
    again = tmp_path / "again.c3d"
    again.write_bytes(c3d_file.read_bytes())
    copied = run(c3d_file, again)
    assert copied.returncode == 1
    assert f"{again}: trial 1 of subject 'P01' holds the samples of trial 0" in (
        copied.stderr
    )


def test_not_a_c3d_file(tmp_path: pathlib.Path) -> None:
    """A file that is not C3D says so."""
    path = tmp_path / "bad.c3d"
    path.write_bytes(b"no c3d here" * 50)
    with pytest.raises(DemoFileError, match="not a readable C3D file"):
        read_c3d(path, MarkerMap.model_validate(MAP))


@pytest.mark.parametrize(
    ("content", "message"),
    [
        ("{not json", "not valid JSON"),
        ('{"shoulder": "A", "elbow": "B"}', "wrist"),
        (
            '{"shoulder": "A", "elbow": "B", "wrist": "C", "axes": ["x", "x", "z"]}',
            "axes",
        ),
        ('{"shoulder": "A", "elbow": "B", "wrist": "C", "units": "inch"}', "units"),
    ],
)
def test_bad_marker_maps(tmp_path: pathlib.Path, content: str, message: str) -> None:
    """A marker map that is not JSON or misses a field names the problem."""
    path = tmp_path / "map.json"
    path.write_text(content)
    with pytest.raises(DemoFileError, match=message):
        read_marker_map(path)


def test_cli_imports_c3d_to_mcap_and_fits(
    tmp_path: pathlib.Path, c3d_file: pathlib.Path
) -> None:
    """armplan demos import writes the MCAP form; armplan fit learns from it."""
    markers = tmp_path / "map.json"
    markers.write_text(json.dumps(MAP))
    out = tmp_path / "imported.mcap"
    run = subprocess.run(
        [
            *(sys.executable, "-m", "armplan", "demos", "import", str(c3d_file)),
            *("--markers", str(markers), "-o", str(out)),
        ],
        capture_output=True,
        text=True,
        timeout=120,
        check=False,
    )
    assert run.returncode == 0, run.stderr
    demos = read_demos(out)
    assert list(demos.subjects) == ["P01"] and len(demos.trials) == 1
    assert demos.trials[0].labels is None
    from services.fit import fit_model
    from services.fit.fitting import MIN_TRIALS
    from shared.demos import DemoSet

    model = fit_model(DemoSet(demos.subjects, demos.trials * MIN_TRIALS))
    assert model.samples == MIN_TRIALS * len(demos.trials[0].times)
    assert "S_R E_P W_P" in model.primitives


def test_a_thumb_marker_lost_for_the_whole_take_is_named(
    tmp_path: pathlib.Path, recorded: Recorded
) -> None:
    """A thumb marker that fell off before the take was told only as "0 of
    its 100 frames have all of the markers RSHO, RELB, RWRB, RWRA", leaving
    the lab to find which; it is named, and said to be optional."""
    zeros = np.zeros_like(recorded.wrist)
    tracks = [_to_lab(p) for p in (zeros, recorded.elbow, recorded.wrist)]
    tracks.append(np.full_like(tracks[0], np.nan))
    path = tmp_path / "thumbless.c3d"
    _write_points(path, list(MAP_NAMES), tracks)
    with pytest.raises(DemoFileError) as caught:
        read_c3d(path, MarkerMap.model_validate(MAP))
    frames = len(recorded.wrist)
    assert caught.value.message == (
        f"{path}: subject 'P01', trial 0: 0 of its {frames} frames have all of "
        "the markers RSHO, RELB, RWRB, RWRA (a frame with a missing marker is "
        "filled only between frames that have it); a trial needs at least 2: "
        "thumb 'RWRA' is in no frame (the thumb marker is optional: a map "
        "without it imports the arm without the forearm's roll)"
    )
    plain = MarkerMap.model_validate({k: v for k, v in MAP.items() if k != "thumb"})
    assert read_c3d(path, plain)[0].wrist_frame is None


@pytest.mark.parametrize(
    ("axes", "said"),
    [
        (["-z", "-x", "y"], None),  # the lab's own: Y up, -z forward
        (["-z", "x", "-y"], "the elbow starts {above:.2f} m above the shoulder"),
        (["z", "x", "y"], "the reach ends {behind:.2f} m behind the shoulder"),
    ],
    ids=["right", "upside-down", "backwards"],
)
def test_a_map_whose_axes_turn_the_arm_wrongly_is_noted(
    c3d_file: pathlib.Path, recorded: Recorded, axes: list[str], said: str | None
) -> None:
    """A wrong rotation (up taken for down, backwards for forward) passes
    every check of the map and imported without a word; the import notes
    an elbow that starts above the shoulder or a reach that ends behind
    it (a demonstration starts hanging and reaches in front). The figures
    are the recorded arm's: its elbow's drop, its wrist's reach forward."""
    notes: list[str] = []
    markers = MarkerMap.model_validate({**MAP, "axes": axes})
    read_c3d(c3d_file, markers, report=notes.append)
    found = [n for n in notes if "is the marker map's" in n]
    if said is None:
        assert found == [], notes
        return
    above, behind = -recorded.elbow[0, 2], recorded.wrist[-1, 0]
    assert [said.format(above=above, behind=behind) in n for n in found] == [True]
