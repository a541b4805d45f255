"""Where the knots of the path parameter u go: "time at the local speed limit".

The path is timed by one scalar u under constant limits on u's speed,
acceleration and jerk, so u should be a parameter along which the path is
equally hard everywhere; otherwise its hardest spot (a kink where a joint
stops against its limit, a change of primitive) slows down all of it.

1. Start from the joint-space chord length scaled by the speed limits:
   knot spacing ``|dq / v|`` [s], the time a step takes at full speed (it
   does not depend on how densely the path was sampled).
2. Find each piece's fastest u speed w from the bounds of |q'|, |q''|,
   |q'''| (:func:`local_speed`).
3. Make w a speed envelope the robot can follow: it may change only as fast
   as the acceleration left over allows (forward and backward passes, in
   closed form with running minima), then smooth it over ``SMOOTHING``
   seconds (a running minimum followed by a running mean never exceeds it).
4. Re-space the knots by it (spacing / envelope), so the kinks get the time
   they need and the rest of the path keeps its speed.

Steps 2-4 run ``PASSES`` times; :func:`fit_spline` keeps whichever spline
(the plain one included) its slowest piece lets cross fastest. The geometry
is untouched: every spline passes through every path point.
"""

from __future__ import annotations

import numpy as np

from services.timing.path_spline import DerivativeBounds, PathSpline
from shared.robot.motion_limits import MotionLimits

#: Share of the acceleration and jerk limits the envelope gives to the path's
#: curvature terms (q'' u_dot^2, q''' u_dot^3); the rest lets speed change.
CURVATURE_SHARE = 0.7
#: Time over which the speed envelope is smoothed [s].
SMOOTHING = 0.05
#: Rounds of re-spacing at most.
PASSES = 1
#: A spline whose slowest piece allows at least this share of the median
#: piece's speed is not re-spaced.
EVEN = 0.5


def fit_spline(points: np.ndarray, limits: MotionLimits) -> PathSpline:
    """The spline through ``points`` (K, n), K >= 2, with knots as described above.

    Of the plain spline and the re-spaced ones, the one whose slowest piece
    allows the shortest crossing (length over top speed) is kept; a spline
    whose pieces are already about equally fast (slowest at least ``EVEN``
    of the median) is not re-spaced. Consecutive points must differ (remove
    repeats first).
    """
    spline = PathSpline(
        points, step_times(points, limits.velocity), limits.lower, limits.upper
    )
    best, best_time = spline, np.inf
    for round_ in range(PASSES + 1):
        speed = local_speed(spline.bounds(), limits)
        time = spline.length / float(speed.min())
        if time < best_time:
            best, best_time = spline, time
        if round_ == PASSES or speed.min() >= EVEN * np.median(speed):
            break
        envelope = speed_envelope(spline.widths, spline.bounds(), speed, limits)
        spline = PathSpline(
            points, spline.widths / envelope, limits.lower, limits.upper
        )
    return best


def step_times(points: np.ndarray, velocity: np.ndarray) -> np.ndarray:
    """Length of each step in speed-scaled joint space, |dq / v| [s], (K - 1,)."""
    return np.linalg.norm(np.diff(points, axis=0) / velocity, axis=1)


def local_speed(bounds: DerivativeBounds, limits: MotionLimits) -> np.ndarray:
    """Fastest u_dot each piece allows, shape (K - 1,).

    The smallest over joints of v / |q'|, sqrt(s a / |q''|) and
    cbrt(s j / |q'''|), with s = ``CURVATURE_SHARE``.
    """
    share = CURVATURE_SHARE
    with np.errstate(divide="ignore"):
        speed = np.minimum(
            limits.velocity / bounds.first,
            np.sqrt(share * limits.acceleration / bounds.second),
        )
        speed = np.minimum(speed, np.cbrt(share * limits.jerk / bounds.third))
    return np.min(speed, axis=1)


def speed_envelope(
    widths: np.ndarray,
    bounds: DerivativeBounds,
    speed: np.ndarray,
    limits: MotionLimits,
) -> np.ndarray:
    """A smooth u speed envelope below each piece's fastest speed, (K - 1,).

    Between pieces the envelope changes at most by the acceleration the
    curvature share leaves, ``(1 - share) a / |q'|`` [1/s^2] times the time
    to cross the piece at its own fastest speed. ``speed`` is
    :func:`local_speed` of ``bounds``.
    """
    with np.errstate(divide="ignore"):
        slope = np.min((1.0 - CURVATURE_SHARE) * limits.acceleration / bounds.first, 1)
    step = slope * widths / speed
    rise = np.cumsum(step)
    forward = rise + np.minimum.accumulate(speed - rise)
    fall = np.cumsum(step[::-1])
    backward = (fall + np.minimum.accumulate(speed[::-1] - fall))[::-1]
    envelope = np.minimum(speed, np.minimum(forward, backward))
    crossing = float(np.mean(widths / envelope))
    radius = max(1, round(SMOOTHING / (2.0 * crossing)))
    return np.exp(_opening(np.log(envelope), radius))


def _opening(values: np.ndarray, radius: int) -> np.ndarray:
    """Running minimum then running mean over 2 radius + 1 values; <= ``values``.

    Each output is a mean of minima over windows that all contain its own
    position, so it never exceeds the input there. Ends repeat the edge value.
    """
    radius = min(radius, len(values) - 1)
    if radius < 1:
        return values
    width = 2 * radius + 1
    padded = np.concatenate(
        (np.full(radius, values[0]), values, np.full(radius, values[-1]))
    )
    low = padded[: len(values)].copy()
    for shift in range(1, width):
        np.minimum(low, padded[shift : shift + len(values)], out=low)
    padded = np.concatenate((np.full(radius, low[0]), low, np.full(radius, low[-1])))
    total = np.concatenate(([0.0], np.cumsum(padded)))
    return (total[width:] - total[:-width]) / width


__all__ = ["fit_spline", "local_speed", "speed_envelope", "step_times"]
