"""Time a joint path with Ruckig without bending it.

1. Corners (:mod:`services.timing.corners`): where the path turns sharply
   the arm stops, and each section is timed on its own.
2. Each section becomes a C2 quintic spline q(u) through every one of its
   points, inside the joint ranges (:mod:`services.timing.path_spline`). The
   parameter u is, by default, the joint-space chord length scaled by the
   speed limits; a caller may give its own, e.g. the hand's arc length along
   an IK path, so that a bell-shaped motion of u is a bell-shaped hand speed,
   as people move (see :func:`knot_widths`).
3. Ruckig (community edition: one degree of freedom, rest to rest, no
   waypoints, never ``intermediate_positions``) times u: the human bell of a
   given duration (:mod:`services.timing.human_pace`), or the fastest
   profile (the better of the bell and the time-optimal profile under
   constant limits on u).
4. The joints' speed, acceleration and jerk follow from the chain rule,
   evaluated at four times the sample rate, and on each side of every knot
   and phase boundary, where the jerk steps
   (:mod:`services.timing.judged_points`). A time-optimal profile under
   limits (V / r, A / r^2, J / r^3) is the same profile run r times slower,
   and the joints' derivatives then shrink by exactly r, r^2 and r^3, so one
   evaluation tells the smallest r that fits every limit: the profile is
   stretched by it once (and to a whole number of sample periods), never
   shortened below the human duration.

Every result also passes :func:`services.timing.check.check_limits` on its
samples (divided differences, independent of Ruckig's word), and
:func:`services.timing.played_check.check_played` on the curve the robot
plays between them (the cubic Hermite curve through the samples' positions
and velocities, whose acceleration can exceed the samples' where the jerk
changes inside a step); should either fail, the limits are tightened (by
``TIGHTEN``, or by what the played curve went over:
:func:`~services.timing.played_check.retime_limits`) and the timing redone,
``RETRIES`` times at most.
"""

from __future__ import annotations

import math

import numpy as np
import numpy.typing as npt

from services.timing.check import check_limits, check_path
from services.timing.corners import corner_indices, sections
from services.timing.human_pace import bell_limits
from services.timing.judged_points import judged
from services.timing.parameter_limits import ParameterLimits, parameter_limits
from services.timing.path_spline import PathSpline
from services.timing.played_check import check_played, retime_limits
from services.timing.scalar_profile import ScalarProfile, plan_rest_to_rest, scaled
from services.timing.trajectory import TimedTrajectory, concatenate
from shared.errors import InvalidInputError, LimitViolationError, TimingError
from shared.robot.motion_limits import MotionLimits

#: Default sample rate [Hz].
RATE = 100.0
#: Path points closer than this to the previous one are repeats [rad].
REPEAT = 1e-9
#: A path parameter that changes less than this from end to end stands still
#: (its steps are rounding noise, a meaningless scale for the knots).
STILL = 1e-9
#: Times the limits are tightened if a sampled result fails its check.
RETRIES = 3
#: Factor applied to the limits at each retry.
TIGHTEN = 0.8
#: Evaluations of the joints' derivatives per sample period, per spline
#: piece and per Ruckig phase, at least, when fitting the stretch.
OVERSAMPLE, PER_KNOT, PER_PHASE = 4, 8, 32
#: Share of a section's mean knot width that a caller's parameter may not go
#: below: where the hand stands still the joints may still move.
FLOOR = 0.2


def time_path(
    q: npt.ArrayLike,
    limits: MotionLimits,
    *,
    duration: float | None = None,
    rate: float = RATE,
    parameter: npt.ArrayLike | None = None,
) -> TimedTrajectory:
    """A jerk-limited trajectory along the joint path ``q``, at rest at both ends.

    Args:
        q: Joint path [rad], shape (n, joints), n >= 2, within the ranges.
        limits: The joints' ranges and speed, acceleration and jerk limits.
        duration: Wanted duration [s] with a minimum-jerk-like bell profile,
            or None for the fastest of two candidates (:func:`fit_profile`):
            the bell stretched until it first touches a limit, or the
            time-optimal profile under constant limits on u. Not the
            time-optimal timing of the path: a bell touches a limit at one
            instant and stays below the limits elsewhere. The result takes
            longer if the limits need it, and is rounded up to whole periods.
        rate: Sample rate [Hz].
        parameter: The path parameter at each point, shape (n,),
            non-decreasing (e.g. the hand's arc length along the path [m]);
            None: the speed-scaled joint chord length.

    Returns:
        Samples every ``1 / rate`` s from 0 to the duration; the first and
        last positions are the path's ends.

    Raises:
        InvalidInputError: malformed path (wrong shape, NaN/inf, all points
            equal) or a bad duration, rate or parameter; names the point.
        JointLimitError: a path point outside a joint's range.
        TimingError: no timing within the limits was found.
    """
    path = check_path(q, limits, minimum=2)
    period = sample_period(rate)
    _check_duration(duration)
    given = _check_parameter(parameter, len(path))
    points, index = distinct_points(path)
    spans = sections(len(points), corner_indices(points, limits.velocity))
    widths = knot_widths(points, None if given is None else given[index], limits)
    splines = [
        PathSpline(points[a : b + 1], widths[a:b], limits.lower, limits.upper)
        for a, b in spans
    ]
    lengths = np.array([spline.length for spline in splines])
    wanted = [
        None if duration is None else duration * share
        for share in lengths / lengths.sum()
    ]
    pieces = [index[a : b + 1] for a, b in spans]
    tight = limits
    for attempt in range(1, RETRIES + 2):
        result = _timed(splines, pieces, tight, wanted, period)
        try:
            check_limits(result.times, result.positions, limits)
        except LimitViolationError as error:
            failure, tight = error, limits.scaled(TIGHTEN**attempt)
            continue
        try:
            check_played(result, limits)
        except LimitViolationError as error:
            failure, tight = error, retime_limits(result, limits, tight)
            continue
        return result
    raise TimingError(
        f"no timing within the limits after {RETRIES} retries: {failure.message}",
        violation=failure.to_wire(),
    )


def knot_widths(
    points: np.ndarray, parameter: np.ndarray | None, limits: MotionLimits
) -> np.ndarray:
    """Spacing of consecutive path points in u, shape (K - 1,).

    Without a parameter: the speed-scaled joint chord |dq / v| [s], floored
    smoothly at ``FLOOR`` times its mean: crowded points (a joint dwelling at
    its limit) would otherwise give pieces hundreds of times shorter than
    their neighbours, and the quintic's higher derivatives on them drown in
    rounding error.

    With a parameter: its increments, with the chord (rescaled to the
    parameter's mean step) added in quadrature at ``FLOOR`` weight, so that a
    stretch where the parameter stands still (the hand waits while the arm
    turns) still gets room; a parameter that stands still all along, but
    for rounding noise (``STILL``: the wrist turning in place), gives the
    chord alone. No floor: near the ends
    of a reach the hand creeps (minimum jerk) and the joints with it, so
    both terms shrink together and q(u) stays nearly straight; a floor would
    bend it there.
    """
    chord = np.linalg.norm(np.diff(points, axis=0) / limits.velocity, axis=1)
    if parameter is None:
        return np.sqrt(chord**2 + (FLOOR * chord.mean()) ** 2)
    step = np.diff(parameter)
    if parameter[-1] - parameter[0] <= STILL:  # a turn in place: chord alone
        return knot_widths(points, None, limits)
    scale = FLOOR * step.mean() / chord.mean()
    return np.sqrt(step**2 + (scale * chord) ** 2)


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


def fit_profile(
    spline: PathSpline, limits: MotionLimits, duration: float | None, period: float
) -> ScalarProfile:
    """u(t) along ``spline``: the bell of ``duration`` [s], or the fastest (None).

    The fastest bell is found once: Ruckig's bell of 1 s, stretched by the
    factor the joints need. A human bell of ``duration`` is that same profile
    run slower, so it keeps every limit whenever it is not shorter; if it
    would be, the fastest bell is the answer. The fastest timing is the
    shorter of the fastest bell and the time-optimal profile under constant
    limits on u. Durations are whole numbers of ``period``.
    """
    length = spline.length
    bell = _fitted(spline, bell_limits(length, 1.0), limits, period)
    if duration is not None:
        if bell.duration >= duration:
            return bell
        periods = math.ceil(duration / period - 1e-9)
        return plan_rest_to_rest(length, bell_limits(length, periods * period))
    try:
        shape = parameter_limits(spline.bounds(), limits, length)
    except TimingError:
        return bell
    optimal = _fitted(spline, shape, limits, period, shrunk_grid=True)
    return min((bell, optimal), key=lambda profile: profile.duration)


def _fitted(
    spline: PathSpline,
    shape: ParameterLimits,
    limits: MotionLimits,
    period: float,
    shrunk_grid: bool = False,
) -> ScalarProfile:
    """Ruckig's profile under ``shape``, stretched or shrunk to just fit the joints.

    ``shrunk_grid``: judge a profile to be shrunk on the grid of the shrunk
    one (see ``required_stretch``).
    """
    profile = plan_rest_to_rest(spline.length, shape)
    factor = required_stretch(spline, profile, limits, period, shrunk_grid)
    periods = max(math.ceil(profile.duration * factor / period - 1e-9), 1)
    return plan_rest_to_rest(
        spline.length, scaled(shape, periods * period / profile.duration)
    )


def required_stretch(
    spline: PathSpline,
    profile: ScalarProfile,
    limits: MotionLimits,
    period: float,
    shrunk_grid: bool = False,
) -> float:
    """Smallest r such that the profile run r times slower keeps every limit.

    Joint speed scales by 1 / r, acceleration by 1 / r^2, jerk by 1 / r^3;
    they are evaluated ``OVERSAMPLE`` times per sample period of the profile,
    and at least ``PER_KNOT`` times per spline piece and ``PER_PHASE`` times
    per Ruckig phase (a short profile, stretched a lot, must not have been
    judged on a handful of points). With ``shrunk_grid``, a profile to be
    shrunk (r < 1) is judged per sample period of the shrunk one: the
    time-optimal profile under the path's constant limits on u can be 20
    times too slow (21 s for a 1 s reach), and 8500 evaluations made the
    fastest timing cost 5 times the human-paced one. (The human bells keep
    the full grid: judged on the shrunk one, some came out a period short,
    failed the final check and were retried slower.)
    """
    floor = 1 + max(PER_KNOT * len(spline.widths), PER_PHASE * len(profile.starts))
    periods = math.ceil(profile.duration / period)
    if not shrunk_grid:
        return _stretch_on(
            spline, profile, limits, max(floor, 1 + periods * OVERSAMPLE)
        )
    if periods * OVERSAMPLE < floor:
        return _stretch_on(spline, profile, limits, floor)
    first = _stretch_on(spline, profile, limits, floor)
    shrunk = math.ceil(profile.duration * min(first, 1.0) / period)
    count = 1 + max(shrunk * OVERSAMPLE, floor - 1)
    return first if count <= floor else _stretch_on(spline, profile, limits, count)


def _stretch_on(
    spline: PathSpline, profile: ScalarProfile, limits: MotionLimits, count: int
) -> float:
    """``required_stretch`` judged on ``count`` evenly spaced times and more.

    Also on each side of every knot and phase boundary, and inside every
    spline piece (:mod:`services.timing.judged_points`).
    """
    d = judged(spline, profile, count)
    ud, udd, uddd = d.velocity[:, None], d.acceleration[:, None], d.jerk[:, None]
    speed = np.abs(d.first * ud) / limits.velocity
    accel = np.abs(d.second * ud**2 + d.first * udd) / limits.acceleration
    jerk = (
        np.abs(d.third * ud**3 + 3.0 * d.second * ud * udd + d.first * uddd)
        / limits.jerk
    )
    return float(max(speed.max(), math.sqrt(accel.max()), math.cbrt(jerk.max())))


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


def _check_parameter(parameter: npt.ArrayLike | None, n: int) -> np.ndarray | None:
    """The caller's path parameter, checked: n finite, non-decreasing values."""
    if parameter is None:
        return None
    values = np.asarray(parameter, dtype=float)
    if values.shape != (n,):
        raise InvalidInputError(
            f"parameter has shape {values.shape}, expected ({n},): one per point",
            field="parameter",
        )
    bad = np.flatnonzero(~np.isfinite(values))
    if bad.size:
        raise InvalidInputError(
            f"parameter[{bad[0]}] is {values[bad[0]]}, not a finite number",
            field="parameter",
        )
    back = np.flatnonzero(np.diff(values) < 0.0)
    if back.size:
        k = int(back[0]) + 1
        raise InvalidInputError(
            f"parameter decreases at point {k}: {values[k]:g} < {values[k - 1]:g}",
            field="parameter",
        )
    return values


def _check_duration(duration: float | None) -> None:
    if duration is not None and not (np.isfinite(duration) and duration > 0.0):
        raise InvalidInputError(
            f"duration {duration} s must be a positive number", field="duration"
        )


__all__ = [
    "RATE",
    "distinct_points",
    "fit_profile",
    "knot_widths",
    "sample_period",
    "time_path",
]
