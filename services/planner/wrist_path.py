"""Human-like wrist paths on NAO: a minimum-jerk time law on an arc about the shoulder.

People move the hand along nearly straight paths with a bell-shaped speed
profile, well described by minimum jerk (Flash and Hogan, 1985). NAO's wrist,
though, lives in a thin shell 0.114-0.162 m from the shoulder, and a straight
segment between two points of it often passes through the unreachable inside.
The path here keeps the human time law and follows the shoulder-centred arc
between start and goal (direction turning steadily, distance changing
linearly): the shape a straight human reach takes once retargeted to NAO's
short upper arm and forearm.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from services.ik.iterate import shoulder_arc


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
        The path, from ``start`` (t = 0) to ``goal`` (t = duration), with
        ``ceil(duration * rate) + 1`` samples.
    """
    n = max(2, math.ceil(duration * rate) + 1)
    times = np.linspace(0.0, duration, n)
    dense = np.vstack([start, shoulder_arc(shoulder, start, goal, 1000)])
    progress = minimum_jerk(times / duration)
    index = progress * (len(dense) - 1)
    low = np.floor(index).astype(int).clip(0, len(dense) - 2)
    frac = (index - low)[:, None]
    positions = dense[low] * (1 - frac) + dense[low + 1] * frac
    positions[-1] = goal
    return TimedPath(times, positions)
