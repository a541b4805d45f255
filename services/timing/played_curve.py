"""The curve the robot plays between samples, and its largest speed, acceleration, jerk.

The robot bridge plays a trajectory on the cubic Hermite curve through its
samples' positions and velocities (``bridge.interpolation``). On each piece
(a cubic) the jerk is constant, the acceleration linear (largest at an end)
and the speed quadratic (largest at an end or where the acceleration is
zero), so each has an exact maximum per piece: the samples alone do not
tell what plays.

How far the played curve strays from a timed path ``q`` sampled every ``h``
with its own velocities (``|q'''| <= J`` everywhere, the jerk free to jump):
Taylor with integral remainders gives, on a piece from ``t_k``,

    H''(t_k) - q''(t_k) = (1 / h) integral over 0..h of K(u) q'''(t_k + u) du,
    K(u) = (h - u) (h - 3 u) / h,

where ``K`` integrates to 0 and its absolute value to ``8 h^2 / 27``: the
played acceleration is off by at most ``4 h / 27`` times the jerk's swing
on the piece, ``8 J h / 27`` (6 % of the default acceleration limit at 100
Hz, 24 % at 25 Hz, where the default jerk builds the acceleration in 50
ms). It is off only where the jerk changes inside a piece (Ruckig's phase
boundaries, the spline's knots), so a timing whose acceleration touches its
limit there plays over it: 5 % at 25 Hz in a planned two-target reach. The
played jerk, ``6 (h (v_k + v_(k+1)) - 2 (q_(k+1) - q_k)) / h^3``, is the
trapezoid rule's error over the piece, ``(6 / h^3) integral of u (h - u)
q'''(t_k + u) du``: a weighted mean of the path's jerk (positive weights
summing to 1), never beyond the path's own largest.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from scipy.interpolate import (  # type: ignore[import-untyped]
    CubicHermiteSpline,
    PPoly,
)


class CurveMaxima(NamedTuple):
    """Largest absolute speed, acceleration and jerk on each piece of a curve.

    Each has shape (m - 1, n): piece ``k`` runs from sample ``k`` to ``k + 1``.

    Attributes:
        velocity: [rad/s].
        acceleration: [rad/s^2] (at one of the piece's ends).
        jerk: [rad/s^3] (constant on the piece).
    """

    velocity: np.ndarray
    acceleration: np.ndarray
    jerk: np.ndarray


def played_curve(
    times: np.ndarray, positions: np.ndarray, velocities: np.ndarray
) -> CubicHermiteSpline:
    """The bridge's curve: cubic Hermite through the samples [s, rad, rad/s].

    Args:
        times: Sample times [s], shape (m,), m >= 2, increasing.
        positions: Joint angles [rad], shape (m, n).
        velocities: Joint speeds [rad/s], shape (m, n).
    """
    return CubicHermiteSpline(times, positions, velocities, axis=0)


def curve_maxima(curve: PPoly) -> CurveMaxima:
    """The exact maxima of a piecewise cubic ``curve`` on each of its pieces.

    ``curve``: joint angles [rad] of time [s] (scipy ``PPoly``, e.g.
    :func:`played_curve`), n joints, m breakpoints. Each piece is read from
    its own coefficients: the Hermite curve's acceleration jumps at the
    samples, so a piece's end is not the next piece's start.
    """
    c3, c2, c1 = curve.c[0], curve.c[1], curve.c[2]  # each (m - 1, n)
    h = np.diff(curve.x)[:, None]
    start, end = 2.0 * c2, 6.0 * c3 * h + 2.0 * c2
    with np.errstate(divide="ignore", invalid="ignore"):
        turn = np.where(c3 != 0.0, -c2 / (3.0 * c3), 0.0)  # where a is 0
    turn = np.clip(turn, 0.0, h)
    speed = np.maximum(np.abs(c1), np.abs(3.0 * c3 * h**2 + 2.0 * c2 * h + c1))
    speed = np.maximum(speed, np.abs(3.0 * c3 * turn**2 + 2.0 * c2 * turn + c1))
    return CurveMaxima(
        velocity=speed,
        acceleration=np.maximum(np.abs(start), np.abs(end)),
        jerk=np.abs(6.0 * c3),
    )


__all__ = ["CurveMaxima", "curve_maxima", "played_curve"]
