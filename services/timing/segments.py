"""Multi-target tasks as one trajectory: segments timed apart, with rests between.

A task such as reach, hold, retreat is a list of :class:`Segment`: each a
joint path timed from rest to rest (:func:`~services.timing.time_path.time_path`),
followed by a rest of ``dwell`` seconds at its last point. Consecutive
segments must join (a segment starts where the previous one ended). A
segment whose path does not move (a target the arm is already at) takes no
time: only its dwell is kept, as a rest. Every
segment's duration and every dwell is a whole number of sample periods, so
the whole trajectory is on one uniform grid.

:func:`time_path_with_stops` is the same for one path that stops at given
point indices.

``path_index`` counts along the joined path, where each joint point is
counted once: segment k's point i is ``offset_k + i`` with
``offset_{k+1} = offset_k + len(segment k) - 1``, the numbering of the single
path with stops.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import NamedTuple

import numpy as np
import numpy.typing as npt

from services.timing.time_path import RATE, REPEAT, sample_period, time_path
from services.timing.trajectory import TimedTrajectory, concatenate, hold
from shared.errors import InvalidInputError
from shared.robot.motion_limits import MotionLimits

#: Largest gap between one segment's end and the next one's start [rad].
JOIN_TOLERANCE = 1e-9


class Segment(NamedTuple):
    """One movement of a task.

    Attributes:
        path: Joint path [rad], shape (n, joints), n >= 2.
        duration: Wanted duration [s] (human bell), or None for the fastest.
        dwell: Rest at the segment's end before the next one [s], >= 0.
        parameter: The path parameter at each point (e.g. the hand's arc
            length), or None; see :func:`~services.timing.time_path.time_path`.
    """

    path: npt.ArrayLike
    duration: float | None = None
    dwell: float = 0.0
    parameter: npt.ArrayLike | None = None


def time_segments(
    segments: Sequence[Segment], limits: MotionLimits, *, rate: float = RATE
) -> TimedTrajectory:
    """One trajectory through ``segments``, at rest between them.

    Raises:
        InvalidInputError: no segments, a negative or non-finite dwell, or a
            segment that does not start where the previous one ended (named).
        and whatever :func:`time_path` raises for a segment's path.
    """
    return time_segments_with_rests(segments, limits, rate=rate)[0]


def time_segments_with_rests(
    segments: Sequence[Segment], limits: MotionLimits, *, rate: float = RATE
) -> tuple[TimedTrajectory, list[int]]:
    """:func:`time_segments`, and where each segment's rest begins.

    Returns:
        The trajectory, and for each segment the index of the sample at which
        its movement has ended and its dwell begins, shape (len(segments),).

    Raises:
        as :func:`time_segments`.
    """
    if not segments:
        raise InvalidInputError("a task needs at least one segment", field="segments")
    period = sample_period(rate)
    parts: list[TimedTrajectory] = []
    rests: list[int] = []
    start_time, offset, previous = 0.0, 0.0, None
    for k, segment in enumerate(segments):
        path = np.asarray(segment.path, dtype=float)
        _check_join(k, previous, path)
        still = _still(path)  # already there: no movement, a rest at the join
        part = (
            hold(path[-1], 0.0, 0.0, period, 0.0)
            if still
            else time_path(
                path,
                limits,
                duration=segment.duration,
                rate=rate,
                parameter=segment.parameter,
            )
        )
        parts.append(part.shifted(start_time, offset))
        start_time += part.duration
        rests.append(round(start_time / period))
        rest_at = offset if still else offset + len(path) - 1
        offset += len(path) - 1
        dwell = _dwell_periods(k, segment.dwell, period) * period
        if dwell > 0.0:
            parts.append(hold(path[-1], start_time, dwell, period, rest_at))
            start_time += dwell
        previous = path[-1]
    joined = concatenate(parts)
    return joined._replace(times=np.arange(len(joined.times)) * period), rests


def _still(path: np.ndarray) -> bool:
    """Whether every point of ``path`` (n, joints) repeats its first."""
    return bool(np.all(np.abs(path - path[0]) <= REPEAT))


def time_path_with_stops(
    q: npt.ArrayLike,
    limits: MotionLimits,
    stops: Sequence[int],
    *,
    dwells: Sequence[float] | None = None,
    durations: Sequence[float | None] | None = None,
    rate: float = RATE,
) -> TimedTrajectory:
    """``q`` timed with a stop (zero speed) at each index in ``stops``.

    Args:
        q: Joint path [rad], shape (n, joints).
        limits: The joints' limits.
        stops: Strictly increasing indices 0 < i < n - 1 where the arm stops.
        dwells: Rest at each stop [s], one per stop (default 0).
        durations: Wanted duration of each of the len(stops) + 1 movements
            [s], or None for the fastest (default: all fastest).
        rate: Sample rate [Hz].
    """
    path = np.asarray(q, dtype=float)
    cuts = _cuts(stops, len(path))
    rests = list(dwells) if dwells is not None else [0.0] * len(stops)
    paces = list(durations) if durations is not None else [None] * (len(cuts) - 1)
    if len(rests) != len(stops) or len(paces) != len(cuts) - 1:
        raise InvalidInputError(
            f"{len(stops)} stops need {len(stops)} dwells and {len(stops) + 1} "
            f"durations, got {len(rests)} and {len(paces)}",
            field="stops",
        )
    segments = [
        Segment(path[a : b + 1], pace, rest)
        for a, b, pace, rest in zip(
            cuts[:-1], cuts[1:], paces, [*rests, 0.0], strict=True
        )
    ]
    return time_segments(segments, limits, rate=rate)


def _cuts(stops: Sequence[int], n: int) -> list[int]:
    """[0, *stops, n - 1], checked."""
    cuts = [0, *(int(s) for s in stops), n - 1]
    for k in range(1, len(cuts)):
        if cuts[k] <= cuts[k - 1]:
            raise InvalidInputError(
                f"stop indices must increase strictly within 1..{n - 2}, got "
                f"{list(stops)}",
                field="stops",
                stops=[int(s) for s in stops],
            )
    return cuts


def _check_join(k: int, previous: np.ndarray | None, path: np.ndarray) -> None:
    if previous is None or path.ndim != 2 or len(path) == 0:
        return
    gap = float(np.max(np.abs(path[0] - previous)))
    if gap > JOIN_TOLERANCE:
        raise InvalidInputError(
            f"segment {k} starts {gap:.3g} rad away from where segment {k - 1} "
            "ends: consecutive segments must join",
            field="segments",
            index=k,
            gap=gap,
        )


def _dwell_periods(k: int, dwell: float, period: float) -> int:
    """Dwell as a whole number of periods, rounded up."""
    if not (np.isfinite(dwell) and dwell >= 0.0):
        raise InvalidInputError(
            f"dwell of segment {k} is {dwell} s: it must be >= 0",
            field="dwell",
            index=k,
        )
    return int(np.ceil(dwell / period - 1e-9))


__all__ = [
    "Segment",
    "time_path_with_stops",
    "time_segments",
    "time_segments_with_rests",
]
