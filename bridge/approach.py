"""A slow, smooth move to a trajectory's start posture, as command frames."""

from __future__ import annotations

import math

import numpy as np

from bridge.frames import frame_times
from bridge.limits import FrameLimits
from shared.messages import CommandFrames
from shared.robot import Side

#: Fraction of the speed and acceleration limits the approach may use.
APPROACH_SHARE = 0.25
#: Shortest approach [s].
MIN_DURATION = 0.5


def approach_duration(
    delta: np.ndarray, limits: FrameLimits, share: float = APPROACH_SHARE
) -> float:
    """Length of a cosine move of ``delta`` [rad] (n,) within ``share`` of the limits.

    A move ``q = q0 + delta (1 - cos(pi t / T)) / 2`` peaks at speed
    ``pi |delta| / (2 T)`` and acceleration ``pi^2 |delta| / (2 T^2)``;
    returns the shortest ``T`` [s] keeping both under ``share`` of the limits
    (and at least :data:`MIN_DURATION`).
    """
    size = np.abs(delta)
    by_speed = math.pi * size / (2.0 * share * limits.velocity)
    by_accel = math.pi * np.sqrt(size / (2.0 * share * limits.acceleration))
    return float(max(MIN_DURATION, by_speed.max(), by_accel.max()))


def approach_frames(
    arm: Side,
    current: np.ndarray,
    target: np.ndarray,
    limits: FrameLimits,
    rate: float,
) -> CommandFrames:
    """Frames moving the arm from ``current`` to ``target`` [rad], shape (n,).

    The move is a half cosine in time, slow enough for :data:`APPROACH_SHARE`
    of every joint's speed and acceleration limits.
    """
    current, target = np.asarray(current, float), np.asarray(target, float)
    delta = target - current
    duration = approach_duration(delta, limits)
    times = frame_times(duration, rate)
    phase = np.minimum(times / duration, 1.0)
    blend = 0.5 * (1.0 - np.cos(math.pi * phase))
    positions = current + blend[:, None] * delta
    return CommandFrames(
        arm=arm,
        rate=rate,
        joint_names=list(limits.names),
        start=current.tolist(),
        times=times.tolist(),
        positions=positions.tolist(),
    )
