"""Checks at the boundary: joint paths, sample times, and trajectories vs. limits.

:func:`check_limits` is the one safety check every emitted trajectory passes
(and the robot bridge reuses): positions within range, and velocity,
acceleration and jerk within limits, estimated from the samples alone by
divided differences (see :mod:`services.timing.finite_differences`), so it
does not take the planner's or Ruckig's word for anything.
"""

from __future__ import annotations

import numpy as np
import numpy.typing as npt

from services.timing.finite_differences import (
    REPORTED_AT,
    divided_differences,
    rounding_noise,
)
from shared.errors import InvalidInputError, JointLimitError, LimitViolationError
from shared.robot.limits import POSITION_SLACK
from shared.robot.motion_limits import MotionLimits

#: Relative slack on speed, acceleration and jerk limits (float round-off).
RELATIVE_SLACK = 1e-9


def check_path(q: npt.ArrayLike, limits: MotionLimits, minimum: int = 1) -> np.ndarray:
    """A joint path as a float array, checked; values within 1e-9 rad are clipped.

    Args:
        q: Joint angles [rad], shape (n, joints), one row per path point.
        limits: The joints' limits (names and ranges are used).
        minimum: Fewest path points accepted.

    Returns:
        A new array, shape (n, joints), inside the ranges.

    Raises:
        InvalidInputError: wrong shape, too few points, or NaN/inf (names the
            point and joint).
        JointLimitError: a point outside a joint's range (names the point).
    """
    path = _rows("joint path", q, len(limits.names), minimum)
    _check_finite("joint path", path, limits.names, "path point")
    for k in _outside(path, limits)[:1]:
        joint, _ = _worst_joint(path[k], limits)
        raise JointLimitError(
            limits.names[joint],
            path[k, joint],
            limits.lower[joint],
            limits.upper[joint],
            f"at path point {k}",
        )
    return np.clip(path, limits.lower, limits.upper)


def check_times(times: npt.ArrayLike, minimum: int = 1) -> np.ndarray:
    """Sample times as a float array: 1-D, finite and strictly increasing [s].

    Raises:
        InvalidInputError: naming the first bad sample.
    """
    t = np.asarray(times, dtype=float)
    if t.ndim != 1 or len(t) < minimum:
        raise InvalidInputError(
            f"times must be a list of at least {minimum} numbers, got shape {t.shape}",
            field="times",
        )
    bad = ~np.isfinite(t)
    if np.any(bad):
        k = int(np.argmax(bad))
        raise InvalidInputError(
            f"time at sample {k} is {t[k]}: times must be finite numbers",
            field="times",
            index=k,
        )
    steps = np.diff(t) <= 0.0
    if np.any(steps):
        k = int(np.argmax(steps)) + 1
        raise InvalidInputError(
            f"times must increase: sample {k} (t = {t[k]} s) is not after sample "
            f"{k - 1} (t = {t[k - 1]} s)",
            field="times",
            index=k,
        )
    return t


def check_limits(
    times: npt.ArrayLike, positions: npt.ArrayLike, limits: MotionLimits
) -> None:
    """Raise if a sampled trajectory leaves a range or exceeds a limit.

    Checks, in this order: every position within its range; velocity,
    acceleration and jerk estimated by divided differences within their
    limits. Input must have at least one sample; derivatives need 2, 3 and 4.

    Args:
        times: Sample times [s], shape (m,), strictly increasing.
        positions: Joint angles [rad], shape (m, joints).
        limits: Ranges and limits of the joints.

    Raises:
        InvalidInputError: malformed input (names the sample).
        LimitViolationError: the first violation found, naming joint,
            quantity, value, limit, sample index and time.
    """
    t = check_times(times)
    q = _rows("positions", positions, len(limits.names), 1)
    if len(q) != len(t):
        raise InvalidInputError(
            f"positions has {len(q)} rows but there are {len(t)} times",
            field="positions",
        )
    _check_finite("positions", q, limits.names, "sample")
    _check_positions(t, q, limits)
    estimates = divided_differences(t, q)._asdict()
    noise = rounding_noise(t, q)
    for quantity, limit in (
        ("velocity", limits.velocity),
        ("acceleration", limits.acceleration),
        ("jerk", limits.jerk),
    ):
        _check_quantity(
            t, estimates[quantity], limit, quantity, noise[quantity], limits.names
        )


def _check_positions(t: np.ndarray, q: np.ndarray, limits: MotionLimits) -> None:
    for k in _outside(q, limits)[:1]:
        joint, bound = _worst_joint(q[k], limits)
        raise LimitViolationError(
            limits.names[joint], "position", q[k, joint], bound, k, t[k]
        )


def _worst_joint(row: np.ndarray, limits: MotionLimits) -> tuple[int, float]:
    """The joint of ``row`` (shape (joints,)) furthest out of range, and its bound."""
    below = limits.lower - row
    joint = int(np.argmax(np.maximum(below, row - limits.upper)))
    bound = limits.lower[joint] if below[joint] > 0 else limits.upper[joint]
    return joint, float(bound)


def _check_quantity(
    t: np.ndarray,
    values: np.ndarray,
    limit: np.ndarray,
    quantity: str,
    noise: float,
    names: tuple[str, ...],
) -> None:
    excess = np.abs(values) - (limit * (1.0 + RELATIVE_SLACK) + noise)
    rows = np.flatnonzero(np.any(excess > 0.0, axis=1))
    if len(rows) == 0:
        return
    k = int(rows[0])
    joint = int(np.argmax(excess[k]))
    index = k + REPORTED_AT[quantity]
    raise LimitViolationError(
        names[joint], quantity, abs(values[k, joint]), limit[joint], index, t[index]
    )


def _outside(q: np.ndarray, limits: MotionLimits) -> np.ndarray:
    """Indices of rows with an angle outside its range (beyond float slack)."""
    out = (q < limits.lower - POSITION_SLACK) | (q > limits.upper + POSITION_SLACK)
    return np.flatnonzero(np.any(out, axis=1))


def _rows(what: str, values: npt.ArrayLike, width: int, minimum: int) -> np.ndarray:
    try:
        array = np.array(values, dtype=float)
    except (TypeError, ValueError):
        raise InvalidInputError(
            f"{what} must be rows of {width} numbers", field=what
        ) from None
    if array.ndim != 2 or array.shape[1] != width or len(array) < minimum:
        raise InvalidInputError(
            f"{what} must have shape (n, {width}) with n >= {minimum}, got "
            f"shape {array.shape}",
            field=what,
        )
    return array


def _check_finite(
    what: str, array: np.ndarray, names: tuple[str, ...], row: str
) -> None:
    bad = ~np.isfinite(array)
    if np.any(bad):
        k, joint = (int(i) for i in np.argwhere(bad)[0])
        raise InvalidInputError(
            f"{what}: {names[joint]} at {row} {k} is {array[k, joint]}, "
            "not a finite number",
            field=what,
            index=k,
            joint=names[joint],
        )


__all__ = ["check_limits", "check_path", "check_times"]
