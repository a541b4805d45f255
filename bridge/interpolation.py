"""A trajectory's joint angles at any time, from its samples."""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
import numpy.typing as npt
from scipy.interpolate import CubicHermiteSpline  # type: ignore[import-untyped]

from shared.messages import Trajectory


def positions_at(
    trajectory: Trajectory,
    times: npt.ArrayLike,
    within: tuple[np.ndarray, np.ndarray] | None = None,
) -> np.ndarray:
    """Joint angles of ``trajectory`` at ``times`` [rad], shape (k, n).

    Between samples the angles follow the cubic Hermite curve through the
    samples' positions and velocities (exact for Ruckig's cubic-in-time jerk
    phases to third order, and equal to the samples at the samples' times).
    Before the start the arm is at the first sample; after the end it holds
    the last one.

    Args:
        trajectory: The trajectory.
        times: Times from the trajectory's start (``times[0]``) [s], shape (k,).
        within: The joints' ranges (lower, upper) [rad], each shape (n,), to
            hold the curve in: between samples seconds apart, near a limit,
            the cubic overshoots it (by 0.002 rad at 1 Hz) where the planned
            path, whose samples are within, does not. ``None``: as it comes.
    """
    out = trajectory_curve(trajectory)(times)
    return out if within is None else np.clip(out, within[0], within[1])


def trajectory_curve(trajectory: Trajectory) -> Callable[[npt.ArrayLike], np.ndarray]:
    """The curve of :func:`positions_at`, built once to be read many times.

    Returns:
        A function of times from the trajectory's start [s], shape (k,), to
        joint angles [rad], shape (k, n) (the ranges not held).
    """
    sample_times = np.asarray(trajectory.times) - trajectory.times[0]
    positions = np.asarray(trajectory.positions, dtype=float)
    if len(sample_times) == 1:
        return lambda times: np.repeat(positions, np.size(times), axis=0)
    spline = CubicHermiteSpline(
        sample_times, positions, np.asarray(trajectory.velocities), axis=0
    )
    end = float(sample_times[-1])

    def at(times: npt.ArrayLike) -> np.ndarray:
        t = np.atleast_1d(np.asarray(times, dtype=float))
        return np.asarray(spline(np.clip(t, 0.0, end)))

    return at


def velocities_at(trajectory: Trajectory, times: npt.ArrayLike) -> np.ndarray:
    """Joint speeds of :func:`positions_at`'s curve at ``times`` [rad/s], (k, n).

    The derivative of the cubic Hermite curve: the trajectory's own
    velocities at its samples' times. Before the start and after the end,
    where the curve holds a sample, 0.

    Args:
        trajectory: The trajectory.
        times: Times from the trajectory's start (``times[0]``) [s], shape (k,).
    """
    t = np.atleast_1d(np.asarray(times, dtype=float))
    sample_times = np.asarray(trajectory.times) - trajectory.times[0]
    width = len(trajectory.joint_names)
    if len(sample_times) == 1:
        return np.zeros((len(t), width))
    spline = CubicHermiteSpline(
        sample_times,
        np.asarray(trajectory.positions, dtype=float),
        np.asarray(trajectory.velocities, dtype=float),
        axis=0,
    )
    inside = (t >= 0.0) & (t <= sample_times[-1])
    speeds = np.zeros((len(t), width))
    speeds[inside] = spline.derivative()(t[inside])
    return speeds
