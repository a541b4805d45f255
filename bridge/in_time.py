"""Start no movement its caller will not wait for to the end.

A query's caller waits a known time (``shared.bus.deadline``). A movement
that would end after it is not started: its reply would reach no one, the
arm would move for no one, and the caller's retry would find it busy. The
bridge checks three times (``bridge.robot_bridge``): before contacting the
robot (the trajectory's length alone, the approach not yet known), before
the approach (approach and trajectory), and just before the trajectory's
frames are sent (an approach that took longer than planned, a slow robot).

The movement ends its length after its call has *reached* the robot, and
the answer leaves only once the last readings, the stiffness check and the
report are done (:data:`AFTER`). A large call over a slow link takes
seconds to arrive; :class:`CallDelay` estimates that from the calls before
(the bridge measures each one's ``start_delay``), so an 8 s trajectory at
500 fps is not started for a caller who waits 8.2 s.
"""

from __future__ import annotations

import time
from collections.abc import Callable

from shared.errors import CallerDeadlineError, CallerGoneError

#: Whether the caller of the execution has gone (its session ended).
CallerGone = Callable[[], bool]
#: Time a finished movement's answer still needs: the last readings, the
#: stiffness check, the report and its encoding [s].
AFTER = 0.1
#: Fewest keys in a call for its start delay to be taken as its size's:
#: below, a call's delay is the link's latency, not its bytes (an 8 s
#: trajectory at 25 fps is 1000 keys: its 7 ms delay on loopback, taken as
#: its size's, over-estimated a 500 fps call's by 1.7 times).
LEARN_FROM_KEYS = 5000


class CallDelay:
    """How long a call takes to reach the robot: latency + size, as last seen.

    The latency is the least start delay of the small calls (approaches,
    short or slow trajectories); the time per key (one joint's angle and
    time at one frame) is the last large call's delay less that latency.
    None seen yet: no delay counted, as before.
    """

    def __init__(self) -> None:
        self._latency = 0.0  # [s]
        self._small_seen = False
        self._per_key = 0.0  # [s]

    def estimate(self, keys: int) -> float:
        """The expected delay of a call of ``keys`` keys [s]."""
        return self._latency + keys * self._per_key

    def learn(self, keys: int, start_delay: float) -> None:
        """Note a call of ``keys`` keys that began ``start_delay`` [s] after leaving."""
        if start_delay < 0.0:
            return
        if keys < LEARN_FROM_KEYS:
            if not self._small_seen or start_delay < self._latency:
                self._latency, self._small_seen = start_delay, True
            return
        self._per_key = max(start_delay - self._latency, 0.0) / keys


def check_in_time(
    url: str,
    until: float | None,
    approach: float | None,
    duration: float,
    outcome: str,
    overhead: float = 0.0,
    gone: CallerGone | None = None,
) -> None:
    """Raise unless the movement (and its answer) ends by ``until``.

    Nor if its caller's session has ended (``gone``): interrupted or killed
    while it waited, it will read no answer either.

    Args:
        url: The robot's NAOqi address (for the error).
        until: When the caller's answer must be ready [s, monotonic clock];
            ``None``: a caller without a deadline (the follower, a script).
        approach: The approach still to play [s]; ``None`` if not known yet
            (counted as none).
        duration: The trajectory's length [s].
        outcome: What became of the movement, for the error.
        overhead: The call's expected way to the robot and the answer's
            making [s] (:class:`CallDelay`, :data:`AFTER`).
        gone: Whether the caller's session has ended; None: not known.

    Raises:
        CallerDeadlineError: the caller's time left is shorter than the
            approach, the trajectory and the overhead.
        CallerGoneError: its session has ended (same kind).
    """
    if gone is not None and gone():
        raise CallerGoneError(
            url, approach, duration, outcome=outcome, overhead=overhead
        )
    if until is None:
        return
    left = until - time.monotonic()
    if left < (approach or 0.0) + duration + overhead:
        raise CallerDeadlineError(
            url, left, approach, duration, outcome=outcome, overhead=overhead
        )
