"""Human-like wrist paths on NAO: the hand swings about the shoulder.

People move the hand with a bell-shaped speed profile, well described by
minimum jerk (Flash and Hogan, 1985). NAO's wrist, moreover, lives in a thin
shell 0.114-0.162 m from the shoulder, where a straight segment between two
points often passes through the unreachable inside.

The path here therefore moves the wrist about the shoulder: its direction
from the shoulder turns along a great circle and its distance from the
shoulder changes, both with the same minimum-jerk progress. The hand's
speed is then a bell, and every point lies in the shell when both ends do.

(A variant in which the distance changed only after the first third of the
movement, the shoulder leading and the elbow joining later, was tried. On
NAO, whose ShoulderRoll turns the arm only 18 degrees inwards, a straight
arm cannot point at targets in front of the body, so the joints had to
catch up abruptly and the timing slowed the reaches to twice the human
duration.)
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np


class TimedPath(NamedTuple):
    """Wrist positions at times.

    Attributes:
        times: Sample times from the start [s], shape (n,).
        positions: Wrist positions in the torso frame [m], shape (n, 3).
    """

    times: np.ndarray
    positions: np.ndarray


def minimum_jerk(tau: np.ndarray) -> np.ndarray:
    """Minimum-jerk progress s(tau) = 10 tau^3 - 15 tau^4 + 6 tau^5, tau in [0, 1]."""
    return tau**3 * (10.0 - 15.0 * tau + 6.0 * tau**2)


def reach_path(
    shoulder: np.ndarray,
    start: np.ndarray,
    goal: np.ndarray,
    duration: float,
    rate: float = 100.0,
) -> TimedPath:
    """A reach from ``start`` to ``goal`` sampled at ``rate``.

    Args:
        shoulder: Shoulder position [m], shape (3,).
        start: Wrist position at the start [m], shape (3,).
        goal: Wrist target [m], shape (3,).
        duration: Movement time [s], > 0.
        rate: Samples per second [Hz].

    Returns:
        The path, from ``start`` (t = 0) to ``goal``, sampled exactly every
        ``1 / rate`` s: ``ceil(duration * rate) + 1`` samples, the last at
        ``duration`` rounded up to a whole period.
    """
    n = max(2, math.ceil(duration * rate - 1e-9) + 1)
    times = np.arange(n) / rate
    tau = times / times[-1]
    progress = minimum_jerk(tau)
    a, b = start - shoulder, goal - shoulder
    ra, rb = float(np.linalg.norm(a)), float(np.linalg.norm(b))
    radius = ra + progress * (rb - ra)
    positions = shoulder + _slerp(a / ra, b / rb, progress) * radius[:, None]
    positions[0], positions[-1] = start, goal
    return TimedPath(times, positions)


def _slerp(ua: np.ndarray, ub: np.ndarray, s: np.ndarray) -> np.ndarray:
    """Unit vectors from ``ua`` to ``ub`` on the great circle at fractions ``s``."""
    angle = math.acos(min(max(float(ua @ ub), -1.0), 1.0))
    s = s[:, None]
    if angle < 1e-6:
        out = ua + s * (ub - ua)
    else:
        out = (np.sin((1 - s) * angle) * ua + np.sin(s * angle) * ub) / math.sin(angle)
    return out / np.linalg.norm(out, axis=1, keepdims=True)
