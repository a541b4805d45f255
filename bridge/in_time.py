"""Start no movement its caller will not wait for to the end.

A query's caller waits a known time (``shared.bus.deadline``). A movement
that would end after it is not started: its reply would reach no one, the
arm would move for no one, and the caller's retry would find it busy. The
bridge checks three times (``bridge.robot_bridge``): before contacting the
robot (the trajectory's length alone, the approach not yet known), before
the approach (approach and trajectory), and just before the trajectory's
frames are sent (an approach that took longer than planned, a slow robot).
"""

from __future__ import annotations

import time

from shared.errors import CallerDeadlineError


def check_in_time(
    url: str,
    until: float | None,
    approach: float | None,
    duration: float,
    outcome: str,
) -> None:
    """Raise unless the movement ends by ``until``.

    Args:
        url: The robot's NAOqi address (for the error).
        until: When the caller's answer must be ready [s, monotonic clock];
            ``None``: a caller without a deadline (the follower, a script).
        approach: The approach still to play [s]; ``None`` if not known yet
            (counted as none).
        duration: The trajectory's length [s].
        outcome: What became of the movement, for the error.

    Raises:
        CallerDeadlineError: the caller's time left is shorter than the
            approach and the trajectory.
    """
    if until is None:
        return
    left = until - time.monotonic()
    if left < (approach or 0.0) + duration:
        raise CallerDeadlineError(url, left, approach, duration, outcome=outcome)
