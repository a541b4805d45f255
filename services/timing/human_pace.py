"""A human speed profile for the path parameter: a minimum-jerk-like bell.

People's reaches have a bell-shaped hand speed close to the minimum-jerk
profile (Flash and Hogan, 1985): over a distance L in time T its speed peaks
at 1.875 L/T. A jerk-limited profile cannot be a quintic, but Ruckig's
time-optimal profile under

    V = 1.875 L/T,   A = 5.3 L/T^2,   J = A / (1 - L/(V T) - V/(A T)) = 46.95 L/T^3

takes exactly T (no cruise: the speed rises to V and falls again), peaks at
the minimum-jerk peak speed, and stays within 2.4 % of the peak speed from
the minimum-jerk speed at every instant (A = 5.3 L/T^2 minimises the RMS
difference, 1.2 % of the peak; ``tests/test_timing_human_pace.py`` checks
both). These are upper bounds: where the joint limits are tighter, they win
and the movement takes longer than T.
"""

from __future__ import annotations

import numpy as np

from services.timing.parameter_limits import ParameterLimits

#: Peak speed of the bell, in units of L/T (minimum jerk: 15/8).
PEAK_SPEED = 1.875
#: Peak acceleration of the bell, in units of L/T^2 (best fit to minimum jerk).
PEAK_ACCELERATION = 5.3
#: Jerk of the bell, in units of L/T^3, so that the time-optimal profile takes T.
JERK = PEAK_ACCELERATION / (1.0 - 1.0 / PEAK_SPEED - PEAK_SPEED / PEAK_ACCELERATION)


def bell_limits(length: float, duration: float) -> ParameterLimits:
    """Limits on u whose time-optimal rest-to-rest motion over ``length`` is the bell.

    Args:
        length: Distance in u to travel.
        duration: The bell's duration T [s].
    """
    speed = length / duration
    return ParameterLimits(
        PEAK_SPEED * speed,
        PEAK_ACCELERATION * speed / duration,
        JERK * speed / duration**2,
    )


def minimum_jerk_speed(tau: np.ndarray) -> np.ndarray:
    """Minimum-jerk speed in units of L/T at tau = t/T in [0, 1], shape of tau."""
    return 30.0 * tau**2 * (1.0 - tau) ** 2


__all__ = [
    "JERK",
    "PEAK_ACCELERATION",
    "PEAK_SPEED",
    "bell_limits",
    "minimum_jerk_speed",
]
