"""A slow, smooth move to a trajectory's start posture, as command frames."""

from __future__ import annotations

import numpy as np

from bridge.frames import frame_times
from bridge.limits import FrameLimits
from bridge.minimum_jerk import (
    PEAK_ACCELERATION,
    PEAK_JERK,
    PEAK_SPEED,
    minimum_jerk_blend,
)
from shared.messages import CommandFrames
from shared.robot import Side

#: Fraction of the speed, acceleration and jerk limits the approach may use.
APPROACH_SHARE = 0.25
#: Shortest approach [s].
MIN_DURATION = 0.5


def approach_duration(
    delta: np.ndarray, limits: FrameLimits, share: float = APPROACH_SHARE
) -> float:
    """Length [s] of a minimum-jerk move of ``delta`` [rad] (n,) within the limits.

    A move ``q = q0 + delta b(t / T)`` with the minimum-jerk blend b
    (``bridge.minimum_jerk``) peaks at speed ``PEAK_SPEED |delta| / T``,
    acceleration ``PEAK_ACCELERATION |delta| / T^2`` and jerk ``PEAK_JERK
    |delta| / T^3``; returns the shortest ``T`` keeping all three under
    ``share`` of the limits (and at least :data:`MIN_DURATION`).
    """
    size = np.abs(delta)
    by_speed = PEAK_SPEED * size / (share * limits.velocity)
    by_accel = np.sqrt(PEAK_ACCELERATION * size / (share * limits.acceleration))
    by_jerk = np.cbrt(PEAK_JERK * size / (share * limits.jerk))
    return float(max(MIN_DURATION, by_speed.max(), by_accel.max(), by_jerk.max()))


def approach_frames(
    arm: Side,
    current: np.ndarray,
    target: np.ndarray,
    limits: FrameLimits,
    rate: float,
) -> CommandFrames:
    """Frames moving the arm from ``current`` to ``target`` [rad], shape (n,).

    The move is minimum-jerk in time (at rest at both ends, its acceleration
    starting and ending at zero), slow enough for :data:`APPROACH_SHARE` of
    every joint's speed, acceleration and jerk limits.
    """
    current, target = np.asarray(current, float), np.asarray(target, float)
    delta = target - current
    duration = approach_duration(delta, limits)
    times = frame_times(duration, rate)
    blend = minimum_jerk_blend(np.minimum(times / duration, 1.0))
    positions = current + blend[:, None] * delta
    return CommandFrames(
        arm=arm,
        rate=rate,
        joint_names=list(limits.names),
        start=current.tolist(),
        times=times.tolist(),
        positions=positions.tolist(),
    )
