"""Velocity, acceleration and jerk of sampled positions by divided differences.

For samples ``x(t_0), x(t_1), ...`` at increasing (not necessarily uniform)
times, the k-th divided difference times k! equals the k-th derivative of
*any* smooth curve through the samples at some time inside the window
(mean-value theorem for divided differences). So if a curve keeps its
velocity, acceleration and jerk within limits, these estimates do too, and an
estimate beyond a limit proves that no curve through the samples stays within
it: the right test for "is this sampled trajectory within limits", whoever
made it.

Each estimate is reported at one sample of its window: velocity over
``(k, k+1)`` at sample ``k + 1``, acceleration over ``(k .. k+2)`` at ``k + 1``,
jerk over ``(k .. k+3)`` at ``k + 2``.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np


class Differences(NamedTuple):
    """Derivative estimates of sampled positions.

    Attributes:
        velocity: [rad/s], shape (m - 1, n), window (k, k+1).
        acceleration: [rad/s^2], shape (m - 2, n), window (k .. k+2).
        jerk: [rad/s^3], shape (m - 3, n), window (k .. k+3).
    """

    velocity: np.ndarray
    acceleration: np.ndarray
    jerk: np.ndarray


#: Sample index each estimate is reported at, relative to its window's first.
REPORTED_AT = {"velocity": 1, "acceleration": 1, "jerk": 2}


def divided_differences(times: np.ndarray, positions: np.ndarray) -> Differences:
    """Velocity, acceleration and jerk estimates of samples (see the module doc).

    Args:
        times: Sample times [s], shape (m,), strictly increasing.
        positions: Joint angles [rad], shape (m, n).
    """
    t = times[:, None]
    first = np.diff(positions, axis=0) / np.diff(t, axis=0)
    second = np.diff(first, axis=0) / (t[2:] - t[:-2])
    third = np.diff(second, axis=0) / (t[3:] - t[:-3])
    return Differences(first, 2.0 * second, 6.0 * third)


def rounding_noise(times: np.ndarray, positions: np.ndarray) -> dict[str, float]:
    """Largest change float round-off alone can cause in each estimate.

    About ``2^k eps max|x| / h^k`` for the k-th derivative with the smallest
    spacing ``h`` [s]: slack so that a trajectory exactly at its limits is not
    refused for its last bit. Keys ``"velocity"``, ``"acceleration"``, ``"jerk"``.
    """
    eps = np.finfo(float).eps * max(1.0, float(np.max(np.abs(positions))))
    h = float(np.min(np.diff(times))) if len(times) > 1 else 1.0
    return {
        "velocity": 4.0 * eps / h,
        "acceleration": 8.0 * eps / h**2,
        "jerk": 16.0 * eps / h**3,
    }


__all__ = ["REPORTED_AT", "Differences", "divided_differences", "rounding_noise"]
