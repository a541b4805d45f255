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
    got = point_times(timed, [3, 3])
    assert got == [
        pytest.approx([0.0, 0.02, 0.03]),
        pytest.approx([0.05, 0.06, 0.07]),
    ]


def test_a_point_between_samples_is_passed_at_the_interpolated_time() -> None:
    """Index 0.4 at 10 ms and 1.6 at 20 ms: point 1 at 15 ms."""
    assert point_times(by_index([0, 0.4, 1.6, 2]), [3]) == [
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
    got = point_times(timed, [len(p) for p in paths])
    joined = [t for times in got for t in times]
    assert np.all(np.diff(joined) >= 0.0) and joined[0] == 0.0
    for k, (path, times) in enumerate(zip(paths, got, strict=True)):
        at = np.array([np.interp(times, timed.times, q) for q in timed.positions.T]).T
        assert np.abs(at - path).max() < 1e-4, f"segment {k}"
        assert times[-1] == pytest.approx(timed.times[rests[k]])
    assert got[1][0] == pytest.approx(got[0][-1] + dwells[0])  # left after the rest
    assert got[2][0] == got[1][-1]  # no rest: left as it arrived
