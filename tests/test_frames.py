"""Command frames: a trajectory sampled at the timeline's frame rate."""

from __future__ import annotations

import numpy as np
import pytest

from bridge.frames import frame_times, frame_velocities, frames_from_trajectory
from bridge.interpolation import positions_at
from bridge.minimum_jerk import minimum_jerk_trajectory
from shared.errors import InvalidInputError
from shared.messages import CommandFrames, Trajectory
from shared.robot import load_arm
from shared.robot.postures import rest


def reach(rng: np.random.Generator, side: str = "right") -> Trajectory:
    """Rest -> a random posture well inside the limits -> rest, seeded."""
    limits = load_arm(side).limits
    target = rng.uniform(
        limits.lower + 0.2 * limits.span, limits.upper - 0.2 * limits.span
    )
    return minimum_jerk_trajectory(side, [rest(side), target, rest(side)], [1.03, 0.91])


def test_frame_k_is_at_k_over_rate() -> None:
    """Frames 1..m sit at k / rate and the last one covers the end."""
    times = frame_times(1.03, 25.0)
    assert np.allclose(times, np.arange(1, 27) / 25.0)
    assert times[-1] >= 1.03 > times[-2]
    assert frame_times(0.0, 25.0).tolist() == [0.04]
    assert len(frame_times(2.0, 25.0)) == 50


def test_frames_equal_the_samples_they_coincide_with(rng: np.random.Generator) -> None:
    """Where a frame falls on a 100 Hz sample, it holds exactly that sample."""
    trajectory = reach(rng)
    frames = frames_from_trajectory(trajectory)
    samples = np.asarray(trajectory.positions)
    assert frames.start == trajectory.positions[0]
    for k, t in enumerate(frames.times[:-1]):
        assert np.allclose(frames.positions[k], samples[round(t * 100)], atol=1e-12)


def test_frames_between_samples_follow_the_hermite_curve(
    rng: np.random.Generator,
) -> None:
    """At 30 fps frames fall between samples; they agree with a minimum-jerk
    curve evaluated exactly to 1e-6 rad."""
    delta = np.array([0.5, -0.5, 0.5, 0.5, 0.5])  # within every range
    trajectory = minimum_jerk_trajectory(
        "right", [rest("right"), rest("right") + delta], [1.0]
    )
    frames = frames_from_trajectory(trajectory, 30.0)
    s = np.minimum(np.asarray(frames.times), 1.0)
    exact = rest("right") + delta * (10 * s**3 - 15 * s**4 + 6 * s**5)[:, None]
    assert np.max(np.abs(np.asarray(frames.positions) - exact)) < 1e-6
    assert frames.frame_numbers == list(range(1, 31))


def test_the_arm_holds_the_last_sample_after_the_end(rng: np.random.Generator) -> None:
    """Past the trajectory's end the commanded posture is its last sample."""
    trajectory = reach(rng)
    after = positions_at(trajectory, [trajectory.duration + 0.5])
    assert np.allclose(after[0], trajectory.positions[-1])


def test_frame_velocities_are_the_curves_slopes(rng: np.random.Generator) -> None:
    """At frame 0 and at each frame: the trajectory's own velocity where a
    frame falls on a sample, the Hermite curve's derivative between samples
    (a central difference of the frames' curve agrees), 0 after the end."""
    trajectory = reach(rng)
    frames = frames_from_trajectory(trajectory, 30.0)
    velocities = frame_velocities(trajectory, frames)
    assert velocities.shape == (len(frames.times) + 1, 5)
    samples = np.asarray(trajectory.velocities)
    np.testing.assert_array_equal(velocities[0], samples[0])
    np.testing.assert_allclose(velocities[3], samples[10], atol=1e-9)  # 0.1 s
    t = np.asarray(frames.times[:-1])
    h = 1e-6
    slope = (positions_at(trajectory, t + h) - positions_at(trajectory, t - h)) / (
        2 * h
    )
    np.testing.assert_allclose(velocities[1:-1], slope, atol=1e-6)
    assert frames.times[-1] > trajectory.duration
    assert (velocities[-1] == 0.0).all()
    assert np.abs(velocities).max() > 0.5


def test_frame_velocities_of_other_joints_are_refused(rng: np.random.Generator) -> None:
    """Frames of another trajectory's joints: named, not silently misread."""
    trajectory = reach(rng)
    frames = frames_from_trajectory(trajectory)
    other = frames.model_copy(update={"joint_names": list(frames.joint_names)[::-1]})
    with pytest.raises(InvalidInputError, match="give the trajectory they were made"):
        frame_velocities(trajectory, other)


def test_frames_are_a_message_with_checked_shapes() -> None:
    """CommandFrames refuses ragged rows and times that do not increase."""
    good = {
        "arm": "right",
        "rate": 25.0,
        "joint_names": ["RShoulderPitch"],
        "start": [0.0],
        "times": [0.04, 0.08],
        "positions": [[0.0], [0.1]],
    }
    CommandFrames.model_validate(good)
    with pytest.raises(ValueError, match="times must increase"):
        CommandFrames.model_validate({**good, "times": [0.08, 0.04]})
    with pytest.raises(ValueError, match="positions\\[1\\] has 2 values"):
        CommandFrames.model_validate({**good, "positions": [[0.0], [0.1, 0.2]]})
    with pytest.raises(ValueError, match="above 0"):
        CommandFrames.model_validate({**good, "times": [0.0, 0.04]})
