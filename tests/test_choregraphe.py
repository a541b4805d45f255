"""Choregraphe behavior files: the keys read back are the trajectory's angles."""

from __future__ import annotations

import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pytest

from bridge.choregraphe import (
    NAMESPACE,
    behavior_xml,
    read_behavior,
    timeline_fps,
    timeline_from_xml,
    write_behavior,
)
from bridge.frames import frames_from_trajectory
from bridge.interpolation import positions_at
from bridge.minimum_jerk import minimum_jerk_trajectory
from shared.errors import InvalidInputError
from shared.robot import load_arm
from shared.robot.postures import rest


@pytest.mark.parametrize("side", ["right", "left"])
def test_keys_round_trip_within_0_05_degree(
    side: str, rng: np.random.Generator, tmp_path: Path
) -> None:
    """Reading the file's keys back gives the trajectory's angles at the frame
    times within 0.05 degrees (in fact within the 1e-4 degree written)."""
    limits = load_arm(side).limits
    targets = rng.uniform(
        limits.lower + 0.1 * limits.span, limits.upper - 0.1 * limits.span, (2, 5)
    )
    trajectory = minimum_jerk_trajectory(
        side, [rest(side), *targets, rest(side)], [0.9, 0.7, 1.1]
    )
    frames = frames_from_trajectory(trajectory)
    keys = read_behavior(write_behavior(frames, tmp_path / "behavior.xar"))
    assert keys.fps == 25.0
    assert keys.names == list(trajectory.joint_names)
    for j, name in enumerate(keys.names):
        times = keys.times(name)
        expected = np.degrees(positions_at(trajectory, times)[:, j])
        error = np.abs(np.degrees(keys.angles(name)) - expected)
        assert error.max() < 0.05
        assert error.max() <= 0.5e-4 + 1e-9
        assert np.allclose(times, frames.times)


def test_the_file_is_a_choregraphe_timeline_box(rng: np.random.Generator) -> None:
    """A xar_version 3 project whose root diagram holds one keyed Timeline box:
    fps 25, size = last frame, one degree-unit curve per joint, keys 1..m."""
    trajectory = minimum_jerk_trajectory(
        "right", [rest("right"), rest("right") - [0.3, 0.3, 0.3, -0.3, 0.3]], [0.5]
    )
    frames = frames_from_trajectory(trajectory)
    root = ET.fromstring(behavior_xml(frames))
    ns = {"c": NAMESPACE}
    assert root.tag == f"{{{NAMESPACE}}}ChoregrapheProject"
    assert root.attrib["xar_version"] == "3"
    boxes = root.findall(
        "c:Box/c:Timeline/c:BehaviorLayer/c:BehaviorKeyframe/c:Diagram/c:Box", ns
    )
    assert len(boxes) == 1
    timeline = boxes[0].find("c:Timeline", ns)
    assert timeline is not None
    assert timeline.attrib["fps"] == "25" and timeline.attrib["size"] == "13"
    curves = timeline.findall("c:ActuatorList/c:ActuatorCurve", ns)
    assert [c.attrib["actuator"] for c in curves] == list(trajectory.joint_names)
    assert {c.attrib["unit"] for c in curves} == {"0"}
    frames_written = [int(k.attrib["frame"]) for k in curves[0].findall("c:Key", ns)]
    assert frames_written == list(range(1, 14))
    links = root.findall(".//c:Link", ns)
    assert len(links) == 2


def test_frames_off_the_timeline_grid_are_refused() -> None:
    """A frame that is not on a whole frame of the timeline cannot be written."""
    trajectory = minimum_jerk_trajectory(
        "right", [rest("right"), rest("right") + 0.1], [0.5]
    )
    frames = frames_from_trajectory(trajectory)
    frames = frames.model_copy(update={"times": [0.05, *frames.times[1:]]})
    with pytest.raises(
        InvalidInputError, match=r"frame 1 at t = 0\.050000 s is not on a frame"
    ):
        behavior_xml(frames)


def test_reading_something_else_is_a_clear_error() -> None:
    """Not XML, or XML without a keyed timeline: InvalidInputError."""
    with pytest.raises(InvalidInputError, match="not a Choregraphe behavior"):
        timeline_from_xml("<ChoregrapheProject")
    with pytest.raises(InvalidInputError, match="no Timeline with an ActuatorList"):
        timeline_from_xml("<ChoregrapheProject xar_version='3'/>")


def test_a_fractional_frame_rate_is_refused_naming_it() -> None:
    """Choregraphe's runtime holds fps as an int: frames at 12.5 fps were
    written as fps="12.5" (read as 12 or not at all); now refused, the rate
    shown as given, with the whole rates on either side."""
    trajectory = minimum_jerk_trajectory(
        "right", [rest("right"), rest("right") + 0.1], [0.8]
    )
    frames = frames_from_trajectory(trajectory, 12.5)
    with pytest.raises(InvalidInputError) as caught:
        behavior_xml(frames)
    assert caught.value.field == "rate"
    assert "got 12.5: use 12 or 13 fps" in caught.value.message
    with pytest.raises(InvalidInputError, match="whole number"):
        timeline_fps(29.97)
    assert timeline_fps(30.0) == 30


def test_the_reader_reads_fps_as_the_runtime_does() -> None:
    """A file with fps="12.5" is refused by the reader, not read as 12.5."""
    text = behavior_xml(
        frames_from_trajectory(
            minimum_jerk_trajectory(
                "right", [rest("right"), rest("right") + 0.1], [0.8]
            )
        )
    ).replace('fps="25"', 'fps="12.5"')
    with pytest.raises(InvalidInputError, match=r"fps '12\.5' is not a whole number"):
        timeline_from_xml(text)
