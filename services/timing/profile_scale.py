"""How much slower (or faster) a profile of u must run to keep every joint in limits.

:mod:`services.timing.parameter_limits` asks every piece of the path to cope
with the top speed V, which is safe but wasteful: near the ends, and after a
corner, the arm moves slowly. Here the profile is looked at where it really
is. On a fine time grid (``OVERSAMPLE`` per sample period), each stretch
between two grid times gets bounds of u_dot and |u_ddot| (the mean of its two
ends plus half the stretch times a bound of the next derivative: rigorous,
not sampled) and the bounds M1, M2, M3 of every piece the stretch touches.
The chain rule then gives each joint's worst speed, acceleration and jerk on
that stretch. Running the whole profile r times slower divides them by r,
r^2 and r^3, so

    r = max over stretches and joints of
        max(speed / v, sqrt(acceleration / a), cbrt(jerk / j))

is the exact factor that makes the profile just fit; Ruckig under
(V / r, A / r^2, J / r^3) gives that slower (r > 1) or faster (r < 1)
profile (:func:`services.timing.scalar_profile.scaled`).
"""

from __future__ import annotations

import numpy as np

from services.timing.parameter_limits import ParameterLimits
from services.timing.path_spline import PathSpline
from services.timing.scalar_profile import ScalarProfile
from shared.robot.motion_limits import MotionLimits

#: Grid times per sample period for the check.
OVERSAMPLE = 2


def required_scale(
    spline: PathSpline,
    profile: ScalarProfile,
    u_limits: ParameterLimits,
    limits: MotionLimits,
    period: float,
) -> float:
    """The time-scale factor r that makes ``profile`` just fit ``limits``.

    Args:
        spline: The path q(u).
        profile: u(t), planned under ``u_limits``.
        u_limits: The limits the profile keeps (bound its derivatives).
        limits: The joints' limits.
        period: Sample period [s].
    """
    count = int(np.ceil(profile.duration / period * OVERSAMPLE)) + 1
    times = np.linspace(0.0, profile.duration, max(count, 2))
    u = profile.sample(times)
    step = times[1] - times[0]
    speed = (
        0.5 * (u.velocity[1:] + u.velocity[:-1]) + 0.5 * step * u_limits.acceleration
    )
    accel = np.abs(u.acceleration)
    accel = 0.5 * (accel[1:] + accel[:-1]) + 0.5 * step * u_limits.jerk
    m1, m2, m3 = _touched_bounds(spline, u.position)
    speed, accel = speed[:, None], accel[:, None]
    velocity = m1 * speed / limits.velocity
    acceleration = (m2 * speed**2 + m1 * accel) / limits.acceleration
    jerk = (m3 * speed**3 + 3.0 * m2 * speed * accel + m1 * u_limits.jerk) / limits.jerk
    return float(max(velocity.max(), np.sqrt(acceleration.max()), np.cbrt(jerk.max())))


def _touched_bounds(
    spline: PathSpline, u: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """For each stretch (u_i, u_i+1): max of M1, M2, M3 over the pieces it touches.

    Each shape (len(u) - 1, n). A stretch touches pieces first..last, those of
    its two ends (u is non-decreasing).
    """
    piece, _ = spline.locate(u)
    bounds = spline.stacked_bounds()  # (K, 3 n), last row zeros
    edges = np.column_stack((piece[:-1], piece[1:] + 1)).ravel()
    touched = np.maximum.reduceat(bounds, edges, axis=0)[::2]
    first, second, third = np.split(touched, 3, axis=1)
    return first, second, third


__all__ = ["OVERSAMPLE", "required_scale"]
