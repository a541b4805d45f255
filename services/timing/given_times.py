"""Joint paths timed by the caller: derivatives at the given times, and a check.

``armplan plan --wrist-path FILE.csv`` returns joint angles at exactly the
times of the file, without retiming. The velocities and accelerations the
trajectory message needs come from the samples themselves (second-order
finite differences on the possibly uneven grid, ``numpy.gradient``), and the
samples must pass :func:`~services.timing.check.check_limits`: a timing that
asks more of a joint than its limits allow is refused with the joint, the
quantity and the sample, never sent on. The arm is at rest before the first
sample and after the last, so the samples are checked with two samples of
rest on either side (one step apart, as the bridge sees its frames): a path
that starts or ends at speed is refused, not stopped dead by the robot.
"""

from __future__ import annotations

import numpy as np
import numpy.typing as npt

from services.timing.check import check_limits, check_path, check_times
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
    velocities = _derivative(path, t)
    accelerations = _derivative(velocities, t)
    return TimedTrajectory(
        times=t,
        positions=path,
        velocities=velocities,
        accelerations=accelerations,
        jerks=_derivative(accelerations, t),
        path_index=np.arange(len(t), dtype=float),
    )


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


def _derivative(values: np.ndarray, times: np.ndarray) -> np.ndarray:
    """d values / dt on the (uneven) time grid, second order where possible."""
    if len(times) < 2:
        return np.zeros_like(values)
    if len(times) == 2:
        return np.gradient(values, times, axis=0, edge_order=1)
    return np.gradient(values, times, axis=0, edge_order=2)


__all__ = ["time_given"]
