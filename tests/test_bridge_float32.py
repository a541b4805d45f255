"""Frames are checked as NAOqi holds them: angles and times as 32-bit floats."""

from __future__ import annotations

import numpy as np
import pytest

from bridge import FrameLimits, checked_frames
from bridge.checks import check_frames
from bridge.float32 import held
from bridge.frames import frames_from_trajectory
from bridge.minimum_jerk import minimum_jerk_trajectory
from bridge.timeline_keys import behavior_frames, timeline_keys
from shared.errors import TrajectoryRefusedError
from shared.messages import Trajectory
from shared.robot.postures import rest


def late_move() -> Trajectory:
    """Still for 6 s, then RElbowRoll turns 0.8 rad in 1 s (jerk 48 rad/s^3)."""
    start = rest("right")
    target = start + np.array([0.0, 0.0, 0.0, 0.8, 0.0])
    return minimum_jerk_trajectory("right", [start, start, target], [6.0, 1.0], 1000.0)


def test_frames_that_pass_in_64_bits_but_not_in_32_are_refused() -> None:
    """At 1000 fps, 6 s in, a time rounded to 32 bits moves by up to 2.4e-7 s:
    the third difference of frames a millisecond apart shows a jerk over the
    limit (1.02 times RElbowRoll's) although the move's own is 48 rad/s^3.
    The 64-bit frames passed, and so were sent (the demo's trajectory at 900
    fps, jerk 1.1 times the limit as NAOqi held it)."""
    limits = FrameLimits.for_arm("right")
    frames = frames_from_trajectory(late_move(), 1000.0)
    check_frames(frames, limits, as_held=False)
    with pytest.raises(TrajectoryRefusedError) as caught:
        check_frames(frames, limits)
    assert caught.value.quantity == "jerk" and caught.value.joint == "RElbowRoll"
    assert "rounded to 32-bit floats, as NAOqi holds them" in caught.value.message
    with pytest.raises(TrajectoryRefusedError, match="32-bit floats"):
        checked_frames(late_move(), 1000.0, limits)
    checked_frames(late_move(), 100.0, limits)  # frames further apart pass


def test_frames_on_a_bound_stay_in_range_as_naoqi_holds_them() -> None:
    """A move to RElbowRoll's and RShoulderRoll's upper bounds: the frames
    were held 1e-6 degree inside, which rounding to 32 bits (RElbowRoll in
    angleInterpolation) or the behavior's degrees times TO_RAD in 32 bits
    (RShoulderRoll) took back outside. Held a few 32-bit steps inside, they
    stay in range however the robot holds them, and pass every check."""
    limits = FrameLimits.for_arm("right")
    start = rest("right")
    target = start.copy()
    target[1], target[3] = limits.upper[1], limits.upper[3]
    trajectory = minimum_jerk_trajectory("right", [start, target, target], [1.0, 0.5])
    frames = checked_frames(trajectory, 25.0, limits, behavior=True)
    for rows in (held(frames.positions), held([frames.start])):
        assert (rows <= limits.upper).all() and (rows >= limits.lower).all()
    played = behavior_frames(frames)
    assert (np.array(played.positions) <= limits.upper).all()
    assert np.array(frames.positions)[:, 3].max() > limits.upper[3] - 1e-6


def test_a_behavior_is_checked_as_its_runtime_computes_it() -> None:
    """behavior_frames: times float(frame - start_frame) / fps and angles
    value * TO_RAD, both in 32-bit floats, as Choregraphe's runtime sends
    them."""
    frames = frames_from_trajectory(late_move(), 50.0)
    keys = timeline_keys(frames)
    played = behavior_frames(frames)
    steps = (keys.frames[0] - keys.start_frame).astype(np.float32)
    np.testing.assert_array_equal(played.times, (steps / np.float32(50))[1:])
    degrees = keys.values[3].astype(np.float32)
    radians = degrees * np.float32(np.pi / 180.0)
    np.testing.assert_array_equal(np.array(played.positions)[:, 3], radians[1:])
    assert played.start[3] == radians[0]
