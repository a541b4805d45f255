"""The tangents of a timeline's keys: handles a third of the way, their
slopes the trajectory's velocities, held in the joints' ranges."""

from __future__ import annotations

import math

import numpy as np
import pytest

from bridge.bezier_curve import CurvePeaks, PlayedCurve, played_curve
from bridge.frames import frame_velocities, frames_from_trajectory
from bridge.key_tangents import held_slopes, key_spans, tangent_handles
from bridge.limits import FrameLimits
from bridge.minimum_jerk import minimum_jerk_trajectory
from bridge.timeline_keys import KEY_INSET, timeline_keys
from shared.errors import InvalidInputError
from shared.robot.postures import rest


def test_handles_are_a_third_of_the_way_at_the_slope() -> None:
    """Left handle (-span / 3, -slope span / 3), right (span / 3, slope
    span / 3), span the frames to that neighbour; (0, 0) before the first
    key and after the last, never -0.0."""
    numbers = np.array([1, 2, 5, 6])
    slopes = np.array([[0.3], [-0.6], [0.0], [1.2]])
    before, after = key_spans(numbers)
    np.testing.assert_array_equal(before, [0, 1, 3, 1])
    np.testing.assert_array_equal(after, [1, 3, 1, 0])
    left, right = tangent_handles(numbers, slopes)
    np.testing.assert_allclose(left[:, 0, 0], [0.0, -1 / 3, -1.0, -1 / 3])
    np.testing.assert_allclose(right[:, 0, 0], [1 / 3, 1.0, 1 / 3, 0.0])
    np.testing.assert_allclose(left[:, 0, 1], [0.0, 0.2, 0.0, -0.4])
    np.testing.assert_allclose(right[:, 0, 1], [0.1, -0.6, 0.0, 0.0])
    assert not np.signbit(left[0, 0]).any() and not np.signbit(right[-1, 0]).any()


def test_slopes_are_held_so_that_every_handle_stays_in_range() -> None:
    """A slope leading a handle out of [lower, upper] is cut until it is on
    the bound (on either side of the key); a key on a bound keeps a slope
    leading in, on the side where that keeps its handle in, and gets 0 for
    one leading out; slopes with room are kept."""
    numbers = np.arange(1, 6)
    values = np.array([[0.5], [0.95], [1.0], [0.99], [0.5]])
    slopes = np.array([[0.3], [0.6], [0.3], [-0.09], [0.2]])
    held = held_slopes(numbers, values, slopes, np.array([0.0]), np.array([1.0]))
    # key 1 at 0.95 rising: its right handle 0.95 + 0.6 / 3 > 1: cut to 0.15
    np.testing.assert_allclose(held[:, 0], [0.3, 0.15, 0.0, -0.03, 0.2])
    left, right = tangent_handles(numbers, held)
    for handle in (left, right):
        heights = values + handle[..., 1]
        assert heights.max() <= 1.0 + 1e-15 and heights.min() >= 0.0


def test_a_key_outside_the_range_gets_no_slope() -> None:
    """No slope keeps both handles of a key beyond a bound inside: 0."""
    held = held_slopes(
        np.arange(1, 4),
        np.array([[0.5], [1.2], [0.5]]),
        np.array([[0.0], [0.4], [0.0]]),
        np.array([0.0]),
        np.array([1.0]),
    )
    assert held[1, 0] == 0.0


def test_the_keys_slopes_are_the_trajectorys_velocities_per_frame() -> None:
    """timeline_keys with velocities: each joint's handles carry the
    velocity at the key in degrees per frame (the start's and every
    frame's), the held last posture's keys are level, and written to 1e-9."""
    start = rest("right")
    trajectory = minimum_jerk_trajectory("right", [start, start + 0.4], [0.6])
    frames = frames_from_trajectory(trajectory, 50.0)
    velocities = frame_velocities(trajectory, frames)
    keys = timeline_keys(frames, velocities)
    assert keys.left is not None and keys.right is not None
    m = len(frames.times)
    for j, name in enumerate(keys.names):
        per_frame = np.degrees(velocities[:, j]) / 50.0
        np.testing.assert_allclose(keys.right[j][: m + 1, 1], per_frame / 3, atol=1e-9)
        np.testing.assert_allclose(
            keys.left[j][1 : m + 1, 1], -per_frame[1:] / 3, atol=1e-9
        )
        assert (keys.right[j][m + 1 :, 1] == 0.0).all()
        assert (keys.left[j][m + 1 :, 1] == 0.0).all()
        np.testing.assert_allclose(
            keys.slopes(name)[1:m, 0], velocities[1:m, j], atol=1e-7
        )
    assert np.abs(velocities).max() > 1.0  # it moves, fast


def test_a_key_on_a_bound_is_level_and_the_curve_stays_in_range() -> None:
    """A move to RShoulderRoll's upper bound that goes on pushing (the
    frames held KEY_INSET inside while the planned curve would pass it):
    the held slopes keep every handle, and so the curve, inside the range."""
    limits = FrameLimits.for_arm("right")
    start = rest("right")
    target = start.copy()
    target[1] = limits.upper[1]
    trajectory = minimum_jerk_trajectory("right", [start, target], [0.5])
    pushing = np.array(trajectory.velocities)
    pushing[-20:, 1] += 0.3  # [rad/s], out of the range
    trajectory = trajectory.model_copy(update={"velocities": pushing.tolist()})
    inside = (limits.lower + KEY_INSET, limits.upper - KEY_INSET)
    frames = frames_from_trajectory(trajectory, 25.0, inside)
    velocities = frame_velocities(trajectory, frames)
    assert velocities[-2, 1] > 0.2  # at 0.48 s; the last frame, 0.52 s, holds
    curve = played_curve(timeline_keys(frames, velocities))
    peaks = CurvePeaks(curve)
    assert peaks.highest[:, 1].max() <= limits.upper[1]
    unheld = raw_curve(curve, frames.rate, velocities)
    assert CurvePeaks(unheld).highest[:, 1].max() > limits.upper[1]


def raw_curve(curve: PlayedCurve, fps: float, velocities: np.ndarray) -> PlayedCurve:
    """``curve`` with its frames' handles at ``velocities`` as given, unheld."""
    slopes = np.zeros_like(curve.values)
    slopes[: len(velocities)] = velocities / fps
    numbers = np.arange(len(curve.times))
    left, right = tangent_handles(numbers, slopes)
    return curve._replace(left=left[..., 1], right=right[..., 1])


def test_velocities_of_the_wrong_shape_are_refused() -> None:
    """One row per key (the start and each frame), one column per joint."""
    start = rest("right")
    trajectory = minimum_jerk_trajectory("right", [start, start + 0.1], [0.2])
    frames = frames_from_trajectory(trajectory)
    with pytest.raises(InvalidInputError, match=r"velocities of shape \(5, 5\)"):
        timeline_keys(frames, np.zeros((5, 5)))
    with pytest.raises(InvalidInputError, match="one finite row"):
        timeline_keys(frames, np.full((6, 5), math.nan))
