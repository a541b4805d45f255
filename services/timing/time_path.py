"""Time an IK joint path with Ruckig without bending it.

1. Corners (:mod:`services.timing.corners`): where the path turns sharply the
   arm stops; the path is cut into sections there.
2. Each section becomes a C2 quintic spline q(u) through every one of its
   points (:mod:`services.timing.path_spline`), with knots at "time at the
   local speed limit" (:mod:`services.timing.spacing`), and guaranteed
   bounds of |q'|, |q''|, |q'''| on every piece.
3. Ruckig times the scalar u from rest to rest (one DoF, no waypoints,
   :mod:`services.timing.scalar_profile`), as a human bell or as fast as
   possible, run just slow enough for every joint's speed, acceleration and
   jerk limits by the chain rule (:mod:`services.timing.profile_fit`).
4. Samples every period are q(u(t)) with the chain rule for the derivatives.
   Only u's timing is chosen, so the joint path, and with it the hand path,
   is the input's.

Paces:
    - ``duration=None``: as fast as the limits allow.
    - ``duration=T`` (the human default, see :mod:`services.timing.human_duration`
      and :mod:`services.timing.human_pace`): a minimum-jerk-like bell of T,
      shared among the sections by their length, slowed down where the
      limits do not allow T.

Every result passes :func:`services.timing.check.check_limits` on its samples
(finite differences, not Ruckig's word); if it did not (it should not: the
bounds are guaranteed), the limits are tightened and the timing recomputed,
``RETRIES`` times at most, else :class:`~shared.errors.TimingError`.
"""

from __future__ import annotations

import numpy as np
import numpy.typing as npt

from services.timing.check import check_limits, check_path
from services.timing.corners import corner_indices, sections
from services.timing.path_spline import PathSpline
from services.timing.profile_fit import fit_profile
from services.timing.scalar_profile import ScalarProfile
from services.timing.spacing import fit_spline, step_times
from services.timing.trajectory import TimedTrajectory, concatenate
from shared.errors import InvalidInputError, LimitViolationError, TimingError
from shared.robot.motion_limits import MotionLimits

#: Default sample rate [Hz].
RATE = 100.0
#: Path points closer than this to the previous one are repeats [rad].
REPEAT = 1e-9
#: Times the limits are tightened if a sampled result fails its check.
RETRIES = 3
#: Factor applied to the limits at each retry.
TIGHTEN = 0.8


def time_path(
    q: npt.ArrayLike,
    limits: MotionLimits,
    *,
    duration: float | None = None,
    rate: float = RATE,
) -> TimedTrajectory:
    """A jerk-limited trajectory along the joint path ``q``, at rest at both ends.

    Args:
        q: Joint path [rad], shape (n, joints), n >= 2, within the ranges.
        limits: The joints' ranges and speed, acceleration and jerk limits.
        duration: Wanted duration [s] with a minimum-jerk-like bell profile,
            or None for the fastest timing the limits allow. The result takes
            longer if the limits need it, and is rounded up to whole periods.
        rate: Sample rate [Hz].

    Returns:
        Samples every ``1 / rate`` s from 0 to the duration; the first and
        last positions are the path's ends.

    Raises:
        InvalidInputError: malformed path (wrong shape, NaN/inf, all points
            equal) or a bad duration or rate; names the point.
        JointLimitError: a path point outside a joint's range.
        TimingError: no timing within the limits was found.
    """
    path = check_path(q, limits, minimum=2)
    period = sample_period(rate)
    _check_duration(duration)
    points, index = distinct_points(path)
    spans = sections(len(points), corner_indices(points, limits.velocity))
    splines = [fit_spline(points[a : b + 1], limits) for a, b in spans]
    lengths = np.array(
        [step_times(points[a : b + 1], limits.velocity).sum() for a, b in spans]
    )
    wanted = [
        None if duration is None else duration * share
        for share in lengths / lengths.sum()
    ]
    pieces = [index[a : b + 1] for a, b in spans]
    for attempt in range(RETRIES + 1):
        tight = limits.scaled(TIGHTEN**attempt) if attempt else limits
        result = _timed(splines, pieces, tight, wanted, period)
        try:
            check_limits(result.times, result.positions, limits)
        except LimitViolationError as error:
            failure = error
            continue
        return result
    raise TimingError(
        f"no timing within the limits after {RETRIES} retries: {failure.message}",
        violation=failure.to_wire(),
    )


def _timed(
    splines: list[PathSpline],
    indices: list[np.ndarray],
    limits: MotionLimits,
    durations: list[float | None],
    period: float,
) -> TimedTrajectory:
    """Each section timed from rest to rest, joined on one grid of ``period``."""
    parts, start = [], 0.0
    for spline, index, duration in zip(splines, indices, durations, strict=True):
        profile = fit_profile(spline, limits, duration, period)
        part = _sample(spline, index, profile, period)
        parts.append(part.shifted(start, 0.0))
        start += part.duration
    result = concatenate(parts)
    return result._replace(times=np.arange(len(result.times)) * period)


def distinct_points(path: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Path points without repeats (K, n), and their indices in ``path`` (K,).

    The last point keeps the last index, so it stands for any repeats before it.

    Raises:
        InvalidInputError: every point equals the first (zero-length path).
    """
    step = np.max(np.abs(np.diff(path, axis=0)), axis=1)
    keep = np.concatenate(([True], step > REPEAT))
    index = np.flatnonzero(keep)
    if len(index) < 2:
        raise InvalidInputError(
            f"joint path has zero length: all {len(path)} points equal point 0",
            field="q",
            points=len(path),
        )
    index[-1] = len(path) - 1
    return path[index], index


def _sample(
    spline: PathSpline, index: np.ndarray, profile: ScalarProfile, period: float
) -> TimedTrajectory:
    """q(u(t)) and its derivatives by the chain rule, every ``period`` [s]."""
    count = round(profile.duration / period) + 1
    times = np.arange(count) * period
    u = profile.sample(times)
    s = spline.evaluate(u.position)
    ud, udd, uddd = u.velocity[:, None], u.acceleration[:, None], u.jerk[:, None]
    piece, tau = s.piece, s.tau
    s.position[-1] = spline.control[-1, -1]  # the path's last point, exactly
    tau[-1] = 1.0
    return TimedTrajectory(
        times=times,
        positions=s.position,
        velocities=s.first * ud,
        accelerations=s.second * ud**2 + s.first * udd,
        jerks=s.third * ud**3 + 3.0 * s.second * ud * udd + s.first * uddd,
        path_index=index[piece] + tau * (index[piece + 1] - index[piece]),
    )


def sample_period(rate: float) -> float:
    """The period [s] of a sample rate [Hz]; raises InvalidInputError if not > 0."""
    if not (np.isfinite(rate) and rate > 0.0):
        raise InvalidInputError(
            f"sample rate {rate} Hz must be a positive number", field="rate"
        )
    return 1.0 / rate


def _check_duration(duration: float | None) -> None:
    if duration is not None and not (np.isfinite(duration) and duration > 0.0):
        raise InvalidInputError(
            f"duration {duration} s must be a positive number", field="duration"
        )


__all__ = ["RATE", "distinct_points", "sample_period", "time_path"]
