"""When a timed task passes each point of its segments: by hand, and on Ruckig's
timing of real joint paths, where the arm must be at the point's posture."""

from __future__ import annotations

import numpy as np
import pytest

from services.timing.point_times import point_times
from services.timing.segments import Segment, time_segments_with_rests
from services.timing.trajectory import TimedTrajectory
from shared.robot import ArmModel, motion_limits


def by_index(index: list[float], start: float = 0.0) -> TimedTrajectory:
    """Samples every 10 ms from ``start`` [s] at path indices ``index``."""
    m = len(index)
    still = np.zeros((m, 5))
    times = start + 0.01 * np.arange(m)
    return TimedTrajectory(times, still, still, still, still, np.array(index))


def test_a_rest_splits_the_shared_point_into_arrival_and_departure() -> None:
    """Segment 0 (points 0-2) arrives at point 2 at its first sample there;
    segment 1 (points 2-4) leaves it at the last, after the rest; times are
    from the first sample."""
    timed = by_index([0, 0.5, 1, 2, 2, 2, 3, 4], start=3.0)
    got = point_times(timed, [3, 3], [3, 7])
    assert got == [
        pytest.approx([0.0, 0.02, 0.03]),
        pytest.approx([0.05, 0.06, 0.07]),
    ]


def test_a_point_between_samples_is_passed_at_the_interpolated_time() -> None:
    """Index 0.4 at 10 ms and 1.6 at 20 ms: point 1 at 15 ms."""
    assert point_times(by_index([0, 0.4, 1.6, 2]), [3], [3]) == [
        pytest.approx([0.0, 0.015, 0.03])
    ]


def test_the_arm_is_at_each_point_when_ruckig_s_timing_passes_it(
    arm: ArmModel, rng: np.random.Generator
) -> None:
    """Three joint paths with rests of 0.3 s, none and 0.2 s, timed at 1 kHz:
    at each point's time the trajectory's posture is the point's (within the
    interpolation between samples), each segment's times lie in its own
    movement, and none decreases along the task."""
    ends = [arm.limits.middle + rng.uniform(-0.3, 0.3, 5) for _ in range(4)]
    paths = [
        a + np.linspace(0.0, 1.0, n)[:, None] ** 2 * (b - a)
        for a, b, n in zip(ends, ends[1:], (40, 25, 60), strict=False)
    ]
    dwells = (0.3, 0.0, 0.2)
    segments = [
        Segment(p, duration=0.8, dwell=d) for p, d in zip(paths, dwells, strict=True)
    ]
    timed, rests = time_segments_with_rests(
        segments, motion_limits(arm.limits), rate=1000.0
    )
    got = point_times(timed, [len(p) for p in paths], rests)
    joined = [t for times in got for t in times]
    assert np.all(np.diff(joined) >= 0.0) and joined[0] == 0.0
    for k, (path, times) in enumerate(zip(paths, got, strict=True)):
        at = np.array([np.interp(times, timed.times, q) for q in timed.positions.T]).T
        assert np.abs(at - path).max() < 1e-4, f"segment {k}"
        assert times[-1] == pytest.approx(timed.times[rests[k]])
    assert got[1][0] == pytest.approx(got[0][-1] + dwells[0])  # left after the rest
    assert got[2][0] == got[1][-1]  # no rest: left as it arrived


def test_a_segment_that_does_not_move_is_passed_as_the_previous_rest_ends(
    arm: ArmModel,
) -> None:
    """A reach with a rest of 0.2 s, then one to where the arm already is
    with a rest of 0.45 s (a hand closing there): the second segment's points
    are all passed when the first rest ends, not after the second rest, where
    the path index still stands at them."""
    a, b = arm.limits.middle, arm.limits.middle + 0.3
    moving = a + np.linspace(0.0, 1.0, 30)[:, None] * (b - a)
    still = np.repeat(b[None, :], 12, axis=0)
    timed, rests = time_segments_with_rests(
        [Segment(moving, duration=0.6, dwell=0.2), Segment(still, dwell=0.45)],
        motion_limits(arm.limits),
    )
    got = point_times(timed, [30, 12], rests)
    assert got[0][-1] == pytest.approx(timed.times[rests[0]])
    assert got[1] == pytest.approx([got[0][-1] + 0.2] * 12)
    assert timed.times[-1] == pytest.approx(got[1][-1] + 0.45)


def test_a_first_segment_that_does_not_move_is_passed_at_the_start(
    arm: ArmModel,
) -> None:
    """Already at the first target, resting 0.3 s there, then a reach: the
    first segment's points at 0, the reach's first when the rest ends."""
    a, b = arm.limits.middle, arm.limits.middle - 0.2
    still = np.repeat(a[None, :], 8, axis=0)
    moving = a + np.linspace(0.0, 1.0, 25)[:, None] * (b - a)
    timed, rests = time_segments_with_rests(
        [Segment(still, dwell=0.3), Segment(moving, duration=0.5)],
        motion_limits(arm.limits),
    )
    got = point_times(timed, [8, 25], rests)
    assert got[0] == [0.0] * 8
    assert got[1][0] == pytest.approx(0.3)
    assert got[1][-1] == pytest.approx(timed.times[-1])
