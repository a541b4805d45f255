"""A thumb-side marker that cannot give the forearm's roll is refused, naming
the frame: on the wrist marker, on the forearm's axis, or swapped with it."""

from __future__ import annotations

import pathlib

import ezc3d
import numpy as np
import pytest

from shared.demos.anthropometry import subject_from_stature
from shared.demos.c3d_import import read_c3d
from shared.demos.grid import grid_targets
from shared.demos.markers import MarkerMap
from shared.demos.reach_model import AVERAGE_STYLE, plan_reach, sample_reach
from shared.demos.thumb_marker import FASTEST_TURN, check_turns
from shared.errors import DemoFileError

MARKERS = MarkerMap(
    shoulder="RSHO", elbow="RELB", wrist="RWRB", thumb="RWRA", subject="P01"
)
NAMES = {"wrist": "RWRB", "thumb": "RWRA"}


def _reach() -> dict[str, np.ndarray]:
    """A reach to P14 at 100 Hz [m, torso axes]; the thumb 4 cm across."""
    person = subject_from_stature("P01", 1.74)
    target = grid_targets(person.arm_length)[13]
    reach = sample_reach(plan_reach(person, AVERAGE_STYLE, target), person, 100.0)
    return {
        "RSHO": np.zeros_like(reach.wrist),
        "RELB": reach.elbow,
        "RWRB": reach.wrist,
        "RWRA": reach.wrist + 0.04 * reach.wrist_frame[:, :, 2],
    }


def _write(path: pathlib.Path, markers: dict[str, np.ndarray]) -> pathlib.Path:
    c3d = ezc3d.c3d()
    c3d["parameters"]["POINT"]["RATE"]["value"] = [100.0]
    c3d["parameters"]["POINT"]["LABELS"]["value"] = tuple(markers)
    c3d["parameters"]["POINT"]["UNITS"]["value"] = ["m"]
    frames = len(next(iter(markers.values())))
    cloud = np.ones((4, len(markers), frames))
    for i, points in enumerate(markers.values()):
        cloud[:3, i, :] = points.T
    c3d["data"]["points"] = cloud
    c3d.write(str(path))
    return path


def test_a_clean_thumb_marker_gives_the_palm(tmp_path: pathlib.Path) -> None:
    markers = _reach()
    trial, _ = read_c3d(_write(tmp_path / "ok.c3d", markers), MARKERS)
    assert trial.wrist_frame is not None
    assert trial.wrist_frame.shape == (len(markers["RWRB"]), 3, 3)


def test_swapped_wrist_markers_are_refused_naming_the_frame(
    tmp_path: pathlib.Path,
) -> None:
    """RWRA and RWRB swapped for 6 frames were imported silently, the palm
    normal turned 180 deg there."""
    markers = _reach()
    wrist, thumb = markers["RWRB"].copy(), markers["RWRA"].copy()
    markers["RWRB"][40:46], markers["RWRA"][40:46] = thumb[40:46], wrist[40:46]
    path = _write(tmp_path / "swap.c3d", markers)
    with pytest.raises(DemoFileError) as caught:
        read_c3d(path, MARKERS)
    message = caught.value.message
    assert message.startswith(
        f"{path}: subject 'P01', trial 0: the wrist frame turns 179 deg from "
        "frame 39 (t = 0.39 s) to frame 40 (t = 0.4 s), at 1790"
    )
    assert message.endswith(
        "deg/s: a forearm turns at most about 2865 deg/s (and a turn over 90 deg "
        "between two frames cannot be told from a swap): are the markers 'RWRA' "
        "and 'RWRB' swapped there, or one of them misplaced?"
    )
    assert caught.value.evidence["frame"] == 40


@pytest.mark.parametrize(
    ("where", "frame"),
    [("on-the-wrist", 0), ("on-the-forearm-axis", 0), ("on-the-wrist-a-while", 40)],
)
def test_a_degenerate_thumb_marker_is_refused_naming_the_frame(
    tmp_path: pathlib.Path, where: str, frame: int
) -> None:
    """On the wrist marker, or on the forearm's axis, the thumb marker gives
    no direction across the wrist: the wrist frame came out arbitrary."""
    markers = _reach()
    wrist, elbow = markers["RWRB"], markers["RELB"]
    if where == "on-the-wrist":
        markers["RWRA"] = wrist.copy()
    elif where == "on-the-forearm-axis":
        markers["RWRA"] = wrist + 0.1 * (wrist - elbow)
    else:
        markers["RWRA"][40:45] = wrist[40:45]
    path = _write(tmp_path / "thumb.c3d", markers)
    with pytest.raises(DemoFileError) as caught:
        read_c3d(path, MARKERS)
    assert caught.value.message.startswith(
        f"{path}: subject 'P01', trial 0, frame {frame} (t = {frame / 100:g} s): "
        "the thumb-side marker 'RWRA' is 0.0 mm from the forearm's axis through "
        "the wrist marker 'RWRB' (it must be 10 to 150 mm: a wrist is about 5 cm "
        "across), so the forearm's roll is undefined there"
    )


def _rolling(speed: float, rate: float, jitter: float = 0.0) -> np.ndarray:
    """Frames turning about x at ``speed`` [rad/s] for 0.2 s at ``rate`` [Hz],
    each also turned by ``jitter`` [rad] back and forth, shape (n, 3, 3)."""
    n = round(0.2 * rate) + 1
    angle = speed * np.arange(n) / rate + jitter * (-1.0) ** np.arange(n)
    c, s = np.cos(angle), np.sin(angle)
    one, zero = np.ones(n), np.zeros(n)
    rows = [[one, zero, zero], [zero, c, -s], [zero, s, c]]
    return np.moveaxis(np.array(rows), -1, 0)


@pytest.mark.parametrize(
    ("speed", "rate", "jitter", "refused"),
    [
        (0.8 * FASTEST_TURN, 100.0, 0.0, False),
        (1.2 * FASTEST_TURN, 100.0, 0.0, True),
        (10.0, 1000.0, np.radians(4.0), False),  # a few degrees of jitter
        (0.0, 1000.0, np.radians(15.0), True),  # 30 deg back and forth in 1 ms
        (20.0, 10.0, 0.0, True),  # 115 deg between two frames at 10 Hz
    ],
)
def test_the_fastest_turn_between_frames(
    speed: float, rate: float, jitter: float, refused: bool
) -> None:
    frames = _rolling(speed, rate, jitter)
    times = np.arange(len(frames)) / rate
    if not refused:
        check_turns(frames, times, str, NAMES, "trial 0", "rec.c3d")
        return
    with pytest.raises(DemoFileError, match="are the markers 'RWRA' and 'RWRB'"):
        check_turns(frames, times, str, NAMES, "trial 0", "rec.c3d")


def test_a_thumb_marker_off_in_one_frame_is_refused(tmp_path: pathlib.Path) -> None:
    """2.5 times its median from the forearm's axis in one frame: misplaced."""
    markers = _reach()
    markers["RWRA"][30] += 1.5 * (markers["RWRA"][30] - markers["RWRB"][30])
    path = _write(tmp_path / "thumb.c3d", markers)
    with pytest.raises(DemoFileError) as caught:
        read_c3d(path, MARKERS)
    assert caught.value.message == (
        f"{path}: subject 'P01', trial 0, frame 30 (t = 0.3 s): the thumb-side "
        "marker 'RWRA' is 100.0 mm from the forearm's axis through the wrist "
        "marker 'RWRB', its median 40.0 mm (it must be 10 to 150 mm: a wrist is "
        "about 5 cm across): a marker is misplaced or mislabelled there"
    )
