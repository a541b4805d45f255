"""The minimum-jerk time law (Flash and Hogan 1985) and its inverse.

Flash T., Hogan N. (1985). The coordination of arm movements: an
experimentally confirmed mathematical model. Journal of Neuroscience 5(7),
1688-1703.
"""

from __future__ import annotations

import numpy as np

from shared.demos.rotations import FloatArray


def minimum_jerk(tau: FloatArray) -> FloatArray:
    """Progress s = 10 tau^3 - 15 tau^4 + 6 tau^5, tau clipped to [0, 1]."""
    tau = np.clip(tau, 0.0, 1.0)
    return np.asarray(tau**3 * (10.0 - 15.0 * tau + 6.0 * tau**2), dtype=float)


def minimum_jerk_rates(tau: FloatArray) -> tuple[FloatArray, FloatArray]:
    """ds/dtau and d2s/dtau2 of :func:`minimum_jerk`; 0 outside [0, 1].

    ds/dtau = 30 tau^2 (1 - tau)^2, d2s/dtau2 = 60 tau (1 - tau) (1 - 2 tau):
    both 0 at tau = 0 and 1, so clipping tau gives 0 outside.
    """
    u = np.clip(np.asarray(tau, dtype=float), 0.0, 1.0)
    speed = 30.0 * u**2 * (1.0 - u) ** 2
    acceleration = 60.0 * u * (1.0 - u) * (1.0 - 2.0 * u)
    return np.asarray(speed, dtype=float), np.asarray(acceleration, dtype=float)


def window_progress(times: FloatArray, start: float, end: float) -> FloatArray:
    """Minimum-jerk progress of a motion running from ``start`` to ``end`` [s].

    0 before ``start``, 1 after ``end``; shape of ``times``.
    """
    if end <= start:
        return np.asarray(times >= start, dtype=float)
    return minimum_jerk((times - start) / (end - start))


def time_at_progress(progress: float) -> float:
    """tau in [0, 1] at which the minimum-jerk progress equals ``progress``."""
    target = min(max(progress, 0.0), 1.0)
    low, high = 0.0, 1.0
    for _ in range(60):  # bisection: s is increasing on [0, 1]
        mid = 0.5 * (low + high)
        if float(minimum_jerk(np.array(mid))) < target:
            low = mid
        else:
            high = mid
    return 0.5 * (low + high)
