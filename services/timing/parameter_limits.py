"""Limits on the path parameter u that keep every joint within its limits.

Along q(u(t)), by the chain rule, for every joint i

    velocity      q' u_dot
    acceleration  q'' u_dot^2 + q' u_ddot
    jerk          q''' u_dot^3 + 3 q'' u_dot u_ddot + q' u_dddot

so if |u_dot| <= V, |u_ddot| <= A, |u_dddot| <= J and, on every piece of the
spline, with M1, M2, M3 bounds of |q'|, |q''|, |q'''| there,

    M1 V <= v_i,   M2 V^2 + M1 A <= a_i,   M3 V^3 + 3 M2 V A + M1 J <= j_i,

then the joint stays within v_i, a_i and j_i at every instant, not only at
samples. Many (V, A, J) satisfy these; :func:`parameter_limits` tries a grid
of splits between the terms and keeps the one whose rest-to-rest motion over
the path (closed form, :func:`rest_to_rest_time`) is shortest.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from services.timing.path_spline import DerivativeBounds
from shared.errors import TimingError
from shared.robot.motion_limits import MotionLimits

#: Fractions of the largest feasible u speed, and of the acceleration left
#: at that speed, that the search tries.
SPEED_FRACTIONS = np.array([1.0, 0.85, 0.7, 0.55, 0.4, 0.25])
ACCELERATION_FRACTIONS = np.array([0.9, 0.7, 0.5, 0.3])


class ParameterLimits(NamedTuple):
    """Limits of the path parameter u (units: u per second, u/s^2, u/s^3).

    Attributes:
        velocity: V, bound of |u_dot|.
        acceleration: A, bound of |u_ddot|.
        jerk: J, bound of |u_dddot|.
    """

    velocity: float
    acceleration: float
    jerk: float


def parameter_limits(
    bounds: DerivativeBounds,
    limits: MotionLimits,
    length: float,
    caps: ParameterLimits | None = None,
) -> ParameterLimits:
    """The (V, A, J) that moves fastest over ``length`` of u within all limits.

    Args:
        bounds: Bounds of |q'|, |q''|, |q'''| per piece and joint (K - 1, n).
        limits: The joints' limits.
        length: Total parameter length to travel.
        caps: Upper bounds on V, A and J (for example a human speed profile),
            or None.
    """
    m1 = (bounds.first / limits.velocity).ravel()
    a1, a2 = _per_limit(bounds, limits.acceleration)[:2]
    j1, j2, j3 = _per_limit(bounds, limits.jerk)
    with np.errstate(divide="ignore", invalid="ignore"):
        top = min(1.0 / m1.max(), 1.0 / np.sqrt(a2.max()), 1.0 / np.cbrt(j3.max()))
        cap = caps or ParameterLimits(np.inf, np.inf, np.inf)
        v = np.minimum(SPEED_FRACTIONS * top, cap.velocity)[:, None]  # (s, 1)
        room = np.minimum(
            np.min((1.0 - a2 * v**2) / a1, axis=1, keepdims=True),
            np.min((1.0 - j3 * v**3) / (3.0 * j2 * v), axis=1, keepdims=True),
        )  # (s, 1): largest A the acceleration and the jerk limits leave
        a = np.minimum(ACCELERATION_FRACTIONS * np.maximum(room, 0.0), cap.acceleration)
        v, a = (x.ravel() for x in np.broadcast_arrays(v, a))  # (c,)
        left = 1.0 - j3 * v[:, None] ** 3 - 3.0 * j2 * (v * a)[:, None]
        j = np.minimum(np.min(left / j1, axis=1), cap.jerk)
        ok = (v > 0.0) & (a > 0.0) & (j > 0.0)
        time = rest_to_rest_time(length, v, a, np.where(ok, j, 1.0))
    time = np.where(ok, time, np.inf)
    best = int(np.argmin(time))
    if not ok[best]:
        raise TimingError(
            "no limits on the path parameter keep every joint within its limits",
            length=length,
        )
    return ParameterLimits(float(v[best]), float(a[best]), float(j[best]))


def _per_limit(
    bounds: DerivativeBounds, limit: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """M1, M2, M3 divided by one joint limit each, flattened to (P,)."""
    first, second, third = ((bound / limit).ravel() for bound in bounds)
    return first, second, third


def motion_time(length: float, limits: ParameterLimits) -> float:
    """Shortest rest-to-rest time over ``length`` of u under ``limits`` [s]."""
    v, a, j = (np.array([value]) for value in limits)
    return float(rest_to_rest_time(length, v, a, j)[0])


def rest_to_rest_time(
    length: float, v: np.ndarray, a: np.ndarray, j: np.ndarray
) -> np.ndarray:
    """Shortest time to move ``length`` from rest to rest under V, A, J [s].

    The classic double-S profile, vectorised over the limits (each shape (c,)).
    """
    ramp = np.where(v * j >= a**2, v / a + a / j, 2.0 * np.sqrt(np.abs(v / j)))
    cruise = length / v + ramp
    peak = 0.5 * a * (-a / j + np.sqrt((a / j) ** 2 + 4.0 * length / a))
    with_a = 2.0 * (peak / a + a / j)
    only_j = 4.0 * np.cbrt(length / (2.0 * j))
    short = np.where(peak >= a**2 / j, with_a, only_j)
    return np.where(length >= v * ramp, cruise, short)


__all__ = ["ParameterLimits", "motion_time", "parameter_limits", "rest_to_rest_time"]
