"""Joint paths timed by the caller: derivatives at the given times, and a check.

``armplan plan --wrist-path FILE.csv`` returns joint angles at exactly the
times of the file, without retiming. The velocities and accelerations the
trajectory message needs are those of the curve the positions lie on: the
clamped cubic spline through the samples (C2, at rest at the first and the
last sample). The robot bridge's curve between samples is the cubic Hermite
curve through their positions and velocities, which with the spline's
velocities is the spline itself, so what is checked here is what plays.
(``numpy.gradient`` on an uneven grid gave velocities the positions did not
have: the bridge's curve dipped between samples, its jerk 4 to 8.7 times
the samples'.) The samples' divided differences must pass
:func:`~services.timing.check.check_limits`, and the spline its speed,
acceleration and jerk limits at every instant between them
(:func:`check_curve`, each at its exact maximum on each piece): a timing
that asks more of a joint than its limits allow is refused with the joint,
the quantity, the value, the limit and the sample, never sent on. The
curve's jerk is what the robot plays; the samples' read less (an average
over three pieces), so judged on them alone a path passed at 10 ms with
its curve at 1.7 times the jerk limit and was refused sampled at 5 ms.
The arm is at rest before the first sample and after the last, so the
samples are checked with two samples of
rest on either side (one step apart, as the bridge sees its frames): a path
that starts or ends at speed is refused, not stopped dead by the robot.
"""

from __future__ import annotations

import numpy as np
import numpy.typing as npt
from scipy.interpolate import CubicSpline  # type: ignore[import-untyped]

from services.timing.check import check_limits, check_path, check_times
from services.timing.played_curve import curve_maxima
from services.timing.trajectory import TimedTrajectory
from shared.errors import InvalidInputError, LimitViolationError
from shared.robot.motion_limits import MotionLimits


def time_given(
    times: npt.ArrayLike, q: npt.ArrayLike, limits: MotionLimits
) -> TimedTrajectory:
    """The joint path ``q`` at exactly ``times``, with derivatives, checked.

    Args:
        times: Sample times [s], shape (m,), m >= 1, strictly increasing.
        q: Joint angles [rad], shape (m, joints), one row per time.
        limits: The joints' limits.

    Returns:
        The trajectory at ``times`` (positions are ``q`` unchanged);
        ``path_index`` is 0, 1, 2, ...

    Raises:
        InvalidInputError: malformed input (names the sample).
        JointLimitError: a posture outside a joint's range (names the sample).
        LimitViolationError: the timing is too fast for a joint (names joint,
            quantity, value, limit, sample and time).
    """
    t = check_times(times)
    path = check_path(q, limits)
    if len(path) != len(t):
        raise InvalidInputError(
            f"{len(path)} postures for {len(t)} times: need one per time",
            field="q",
        )
    check_limits(t, path, limits)
    check_rest_ends(t, path, limits)
    if len(t) < 2:
        still = np.zeros_like(path)
        return TimedTrajectory(t, path, still, still, still, np.zeros(1))
    curve = CubicSpline(t, path, bc_type="clamped")
    check_curve(curve, limits)
    velocities = curve(t, 1)
    velocities[[0, -1]] = 0.0  # at rest (evaluated, 1e-19 at the last sample)
    return TimedTrajectory(
        times=t,
        positions=path,
        velocities=velocities,
        accelerations=curve(t, 2),
        jerks=curve(t, 3),
        path_index=np.arange(len(t), dtype=float),
    )


def check_curve(curve: CubicSpline, limits: MotionLimits) -> None:
    """The spline's speed, acceleration and jerk within the limits between samples.

    The curve judged is the one the robot plays (the bridge's cubic Hermite
    curve through the samples' positions and velocities, which is this
    spline), at every instant, not at the samples only. On each piece (a
    cubic) the jerk is constant, the acceleration linear (largest at an
    end) and the speed quadratic (largest at an end or where the
    acceleration is zero): each is checked at its exact maximum, the same
    measure the Ruckig-timed path is judged by between its samples
    (:mod:`services.timing.judged_points`). So the answer does not hang on
    where the samples fall: the samples' divided differences average the
    pieces' jerks and read less (a planner wrist path tracked at 10 ms read
    RElbowYaw jerk 381 rad/s^3 on its samples where its curve played 1102,
    limit 661, and the same wrist curve sampled every 5 ms was refused
    for 864 on its samples).

    Raises:
        LimitViolationError: naming the joint, the quantity and the sample
            the offending piece starts at.
    """
    t = curve.x
    maxima = curve_maxima(curve)  # per piece, (m - 1, n)
    acceleration = np.abs(curve(t, 2))  # continuous: at the samples, (m, n)
    for quantity, values, bound in (
        ("velocity", maxima.velocity, limits.velocity),
        ("acceleration", acceleration, limits.acceleration),
        ("jerk", maxima.jerk, limits.jerk),
    ):
        over = values / bound > 1.0 + 1e-9
        if over.any():
            k, j = np.argwhere(over)[0]
            k = min(int(k), len(t) - 1)
            raise LimitViolationError(
                limits.names[j],
                quantity,
                float(values[k, j]),
                float(bound[j]),
                k,
                float(t[k]),
                context=_where(quantity, k, len(t)),
            )


def _where(quantity: str, k: int, count: int) -> str:
    """Where on the curve a ``quantity`` over its limit at sample ``k`` lies."""
    if quantity == "acceleration" or k + 1 >= count:
        return "on the curve between samples"
    return f"on the curve between samples {k} and {k + 1}"


#: Samples of rest seen before the first sample and after the last.
REST = 2


def check_rest_ends(t: np.ndarray, q: np.ndarray, limits: MotionLimits) -> None:
    """Starting from rest and coming to rest within the limits.

    Args:
        t: Sample times [s], shape (m,), checked.
        q: Joint angles [rad], shape (m, joints), checked.
        limits: The joints' limits.

    Raises:
        LimitViolationError: naming the joint, the quantity and the first or
            last sample, with the path's start or end as the reason.
    """
    if len(t) < 2:
        return
    before = t[0] - (t[1] - t[0]) * np.arange(REST, 0, -1)
    after = t[-1] + (t[-1] - t[-2]) * np.arange(1, REST + 1)
    padded = np.vstack([np.repeat(q[:1], REST, 0), q, np.repeat(q[-1:], REST, 0)])
    try:
        check_limits(np.concatenate([before, t, after]), padded, limits)
    except LimitViolationError as error:
        starting = error.time - t[0] < t[-1] - error.time
        k = 0 if starting else len(t) - 1
        raise LimitViolationError(
            error.joint,
            error.quantity,
            error.value,
            error.limit,
            k,
            float(t[k]),
            context=(
                "to start from rest: the path must start at rest"
                if starting
                else "to stop at the end: the path must end at rest"
            ),
        ) from None


__all__ = ["check_curve", "time_given"]
