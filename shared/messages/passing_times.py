"""Check of when a trajectory passes the points of the paths it was timed from.

A wrist path, its decision and its joint path are sampled on the path's own
clock (100 points a second of the reach's nominal human duration); the
timing stage sets the actual pace, and rests between reaches. When the
trajectory passes each point is then a time on the trajectory's clock
[s from its first sample]. Two points may be passed at the same instant (a
reach's last point and the next reach's first, with no rest between), so
the times need only not decrease.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

from shared.messages.sample_times import MAX_SPAN


def check_passing_times(times: Sequence[float], what: str) -> None:
    """Raise ``ValueError`` (a validation error) unless ``times`` [s] are sane.

    Args:
        times: When each point is passed [s from the trajectory's first
            sample], shape (n,).
        what: The field, named in the message, e.g. ``"trajectory_times"``.

    Raises:
        ValueError: naming the first time that is not finite, negative, past
            ``MAX_SPAN`` (a day) or before the one before it.
    """
    for i, t in enumerate(times):
        if not (math.isfinite(t) and 0.0 <= t <= MAX_SPAN):
            raise ValueError(
                f"{what}[{i}] is {t:g} s: a time from the trajectory's first sample "
                f"is finite and within 0 to {MAX_SPAN:g} s"
            )
        if i and t < times[i - 1]:
            raise ValueError(
                f"{what} must not decrease: {what}[{i}] = {t:.9g} s comes after "
                f"{what}[{i - 1}] = {times[i - 1]:.9g} s"
            )
