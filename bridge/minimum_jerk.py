"""Smooth joint trajectories through postures, for trying the bridge without a planner.

Each segment between two postures follows the minimum-jerk profile
``q = q0 + (q1 - q0) (10 s^3 - 15 s^4 + 6 s^5)``, ``s = t / T``, which starts
and ends at rest: its peak speed is ``PEAK_SPEED |q1 - q0| / T``, its peak
acceleration ``PEAK_ACCELERATION |q1 - q0| / T^2`` and its peak jerk
``PEAK_JERK |q1 - q0| / T^3``.

:func:`minimum_jerk_trajectory` refuses what it cannot make with a typed
error naming it: a posture outside the joints' ranges, a duration that is
not finite, not positive or shorter than one sample, a sample rate that is
not finite and positive. It keeps every duration as given: a segment whose
duration is a whole number of samples is sampled at ``k / rate``; any other
(0.333 s at 100 Hz) is split into ``ceil(T rate)`` equal steps, a little
faster than ``rate``, so that its last sample lands exactly at ``T``.
"""

from __future__ import annotations

import math

import numpy as np
import numpy.typing as npt

from shared.errors import InvalidInputError
from shared.messages import Trajectory
from shared.robot import Side, load_arm
from shared.robot.limits import JointLimits

#: Relative tolerance within which ``T rate`` counts as a whole number of
#: samples (float round-off of durations such as 0.6 s at 100 Hz).
WHOLE = 1e-9
#: Peaks of the blend's first three derivatives in s over [0, 1]: 15/8 at
#: s = 1/2, 10/sqrt(3) at s = 1/2 -+ sqrt(3)/6, and 60 at both ends.
PEAK_SPEED, PEAK_ACCELERATION, PEAK_JERK = 1.875, 10.0 / math.sqrt(3.0), 60.0


def minimum_jerk_blend(s: np.ndarray) -> np.ndarray:
    """``10 s^3 - 15 s^4 + 6 s^5``: 0 at s = 0, 1 at s = 1, at rest at both [-]."""
    return s**3 * (10.0 - 15.0 * s + 6.0 * s**2)


def _profile(s: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Minimum-jerk blend and its first two derivatives in ``s``, each (k,)."""
    blend = minimum_jerk_blend(s)
    speed = 30 * s**2 - 60 * s**3 + 30 * s**4
    accel = 60 * s - 180 * s**2 + 120 * s**3
    return blend, speed, accel


def segment_times(duration: float, rate: float) -> np.ndarray:
    """Times of one segment's samples from its start [s], shape (k,).

    ``duration * rate`` samples at ``1 / rate`` if that is a whole number
    (within ``WHOLE``), else ``ceil(duration * rate)`` equal steps ending
    exactly at ``duration`` (a little shorter than ``1 / rate``).
    """
    count = duration * rate
    whole = round(count)
    if abs(count - whole) <= WHOLE * max(1.0, count):
        return np.arange(1, whole + 1) / rate
    steps = math.ceil(count)
    return duration * np.arange(1, steps + 1) / steps


def _checked_rate(rate: float) -> float:
    rate = float(rate)
    if not (math.isfinite(rate) and rate > 0.0):
        raise InvalidInputError(
            f"rate must be a finite number of samples per second above 0, "
            f"got {rate!r} Hz",
            field="rate",
            rate=rate,
        )
    return rate


def _checked_postures(postures: npt.ArrayLike, limits: JointLimits) -> np.ndarray:
    """``postures`` as an array (p, n), p >= 2, every angle in its joint's range."""
    try:
        q = np.asarray(postures, dtype=float)
    except (TypeError, ValueError):
        q = np.zeros((0,))
    n = len(limits.names)
    if q.ndim != 2 or q.shape[1] != n or len(q) < 2:
        raise InvalidInputError(
            f"postures must be two or more rows of {n} joint angles [rad], got "
            f"shape {np.shape(q)}",
            field="postures",
        )
    if not np.isfinite(q).all():
        i, j = np.argwhere(~np.isfinite(q))[0]
        value = float(q[i, j])
        raise InvalidInputError(
            f"postures[{i}][{j}] ({limits.names[j]}) is {value!r}: angles must "
            "be finite",
            field="postures",
        )
    outside = (q < limits.lower) | (q > limits.upper)
    if outside.any():
        i, j = np.argwhere(outside)[0]
        value = float(q[i, j])
        raise InvalidInputError(
            f"postures[{i}]: {limits.names[j]} at {value!r} rad is outside its "
            f"range [{limits.lower[j]:.4f}, {limits.upper[j]:.4f}] rad",
            field="postures",
            joint=limits.names[j],
        )
    return q


def _checked_durations(durations: npt.ArrayLike, count: int, rate: float) -> np.ndarray:
    """``durations`` as an array (count,), each finite and at least one sample [s]."""
    spans = np.atleast_1d(np.asarray(durations, dtype=float))
    if spans.shape != (count,):
        raise InvalidInputError(
            f"durations must hold one time per segment ({count}), got shape "
            f"{spans.shape}",
            field="durations",
        )
    for i, span in enumerate(spans.tolist()):
        if not (math.isfinite(span) and span * rate >= 1.0 - WHOLE):
            raise InvalidInputError(
                f"durations[{i}] is {span!r} s: a segment must last at least one "
                f"sample ({1.0 / rate:g} s at {rate:g} Hz)",
                field="durations",
                duration=span,
            )
    return spans


def minimum_jerk_trajectory(
    arm: Side | str,
    postures: npt.ArrayLike,
    durations: npt.ArrayLike,
    rate: float = 100.0,
) -> Trajectory:
    """A trajectory through ``postures``, at rest at each one.

    Args:
        arm: Which arm.
        postures: Joint angles to pass through [rad], shape (p, 5), p >= 2,
            each within its joint's range.
        durations: Time of each segment [s], shape (p - 1,), each at least
            one sample (``1 / rate``); kept exactly (``segment_times``).
        rate: Sample rate [Hz].

    Returns:
        The trajectory, with its wrist path from forward kinematics [m] and
        every sample labelled with the all-joints primitive "S_R E_PR W_PR".

    Raises:
        InvalidInputError: naming the posture, the duration or the rate that
            is malformed, out of range or not finite.
    """
    side = Side.parse(arm)
    model = load_arm(side)
    rate = _checked_rate(rate)
    q = _checked_postures(postures, model.limits)
    spans = _checked_durations(durations, len(q) - 1, rate)
    times, pos, vel, acc = (
        [np.zeros(1)],
        [q[:1]],
        [np.zeros((1, 5))],
        [np.zeros((1, 5))],
    )
    offset = 0.0
    for a, b, span in zip(q[:-1], q[1:], spans, strict=True):
        t = segment_times(float(span), rate)
        blend, speed, accel = _profile(t / t[-1])
        delta = b - a
        times.append(offset + t)
        pos.append(a + blend[:, None] * delta)
        vel.append(speed[:, None] * delta / t[-1])
        acc.append(accel[:, None] * delta / t[-1] ** 2)
        offset += t[-1]
    positions = np.vstack(pos)
    wrist = [tuple(model.fk(row).wrist.tolist()) for row in positions]
    return Trajectory(
        arm=side,
        joint_names=list(side.joint_names),
        times=np.concatenate(times).tolist(),
        positions=positions.tolist(),
        velocities=np.vstack(vel).tolist(),
        accelerations=np.vstack(acc).tolist(),
        primitives=["S_R E_PR W_PR"] * len(positions),
        wrist_path=wrist,
    )
