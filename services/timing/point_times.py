"""When a timed task passes each point of its segments' joint paths.

A segment's joint path comes on the wrist path's own clock (100 points a
second of the reach's nominal human duration); the timing sets the actual
pace, and rests between the movements. Point p of the joined path
(numbered as in :mod:`services.timing.segments`: segment k's point i is
``offset_k + i``) is passed where the trajectory's ``path_index`` reaches
p, at the time interpolated linearly in ``path_index`` between the two
samples about it. Where two segments meet, the point is both one segment's
last and the next one's first: the arm arrives there (the first segment's
time), rests for the dwell, and leaves (the next one's time, when its
movement starts). So every segment's times lie within its own movement.

Each segment's points are looked for only among the samples up to its
arrival (the rest's first sample, from
:func:`~services.timing.segments.time_segments_with_rests`): the
``path_index`` stays put through the rest that follows, and through the
whole of a segment that does not move (a target the arm is already at),
so searching the samples after would place the points after the next
rest, such as the hand closing there. A segment that does not move has
all its points at its arrival, which is also when the previous rest ends.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from services.timing.trajectory import TimedTrajectory


def point_times(
    timed: TimedTrajectory, counts: Sequence[int], rests: Sequence[int]
) -> list[list[float]]:
    """When ``timed`` passes each point of each segment [s from its first sample].

    Args:
        timed: The task's trajectory, its ``path_index`` along the joined
            path (:func:`~services.timing.segments.time_segments_with_rests`).
        counts: Points of each segment's path, shape (segments,), each >= 1.
        rests: For each segment, the index of the sample at which it has
            arrived and its rest begins, shape (segments,), non-decreasing
            (as ``time_segments_with_rests`` returns them).

    Returns:
        One list per segment, one time per point, not decreasing along the
        task, within the trajectory's span: a segment's first point when
        the arm leaves it (the end of the previous rest), its last when the
        arm arrives (``times[rests[k]]``).
    """
    index = np.asarray(timed.path_index, dtype=float)
    times = np.asarray(timed.times, dtype=float) - float(timed.times[0])
    passed: list[list[float]] = []
    offset = 0
    for count, rest in zip(counts, rests, strict=True):
        upto = slice(0, int(rest) + 1)  # the samples up to the arrival
        points = offset + np.arange(count, dtype=float)
        segment = reached(index[upto], times[upto], points)
        segment[0] = left(index[upto], times[upto], float(offset))
        passed.append(segment.tolist())
        offset += count - 1
    return passed


def reached(index: np.ndarray, times: np.ndarray, points: np.ndarray) -> np.ndarray:
    """When ``index`` (non-decreasing, (m,)) first reaches each of ``points`` [s].

    Between the sample before and the first sample at or past a point, the
    time is interpolated linearly; a point past the last sample's index is
    reached at the last sample (rounding at the end of the path, or a
    segment that does not move).
    """
    after = np.searchsorted(index, points, side="left")
    last = len(index) - 1
    at = np.minimum(after, last)
    before = np.maximum(at - 1, 0)
    span = index[at] - index[before]
    share = np.divide(
        points - index[before], span, out=np.ones_like(points), where=span > 0.0
    )
    share = np.clip(share, 0.0, 1.0)
    result = times[before] + share * (times[at] - times[before])
    result[after == 0] = times[0]
    result[after > last] = times[last]
    return result


def left(index: np.ndarray, times: np.ndarray, point: float) -> float:
    """When ``index`` (non-decreasing) is last at or before ``point`` [s].

    At a rest: its end, as the movement from the point starts. Given the
    samples up to a segment's arrival, a segment that does not move leaves
    at its arrival.
    """
    at = int(np.searchsorted(index, point, side="right")) - 1
    return float(times[max(at, 0)])
