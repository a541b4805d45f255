"""A running motion command; a blocking ALMotion call is answered when it ends."""

from __future__ import annotations

import threading
from collections.abc import Callable

#: Extra time a blocking call waits past its command's end before failing [s].
GRACE = 5.0
#: The methods whose tasks book their joints, as a NAO's blocking calls do
#: (NAOqi's ``areResourcesAvailable``: "Only motion API's blocking call takes
#: resources"); ``setAngles`` and ``setStiffnesses`` book nothing.
BOOKING = frozenset(
    {"angleInterpolation", "angleInterpolationWithSpeed", "stiffnessInterpolation"}
)

#: How a blocking call is answered: with None (it returns) or the reason it
#: fails.
Answer = Callable[[str | None], None]


class MotionTask:
    """One accepted command on a set of joints.

    A blocking call is answered once, when its task ends (:meth:`answer`),
    not by a thread that waits for it: a NAO answers a stop at once however
    many blocking calls run, and a waiting thread held one of libqi's
    worker threads, so that a stop sent behind a few blocking calls waited
    for libqi to add a thread (0.5 s).

    Attributes:
        method: The ALMotion method that made it.
        joints: Joints it drives.
        start_time: When it took effect, the time its keys count from [s, sim
            clock].
        end_time: When its last key is reached [s, sim clock].
    """

    def __init__(
        self,
        method: str,
        joints: list[str],
        start_time: float,
        end_time: float,
        killed_returns: bool = False,
    ) -> None:
        """A task from ``start_time`` to ``end_time`` [s, sim clock].

        ``killed_returns``: a blocking call whose task is interrupted returns
        normally instead of failing (:meth:`answer`).
        """
        self.method = method
        self.killed_returns = killed_returns
        self.start_time = start_time
        self.joints = joints
        self.end_time = end_time
        self._done = threading.Event()
        self._lock = threading.Lock()  # one outcome, one answer
        self._outcome: tuple[str | None] | None = None  # (reason or None,) once ended
        self._answer: Answer | None = None

    def finish(self) -> None:
        """The command's joints reached their last keys."""
        self._end(None)

    def interrupt(self, reason: str) -> None:
        """Another command took its joints, or everything was stopped."""
        self._end(
            None if self.killed_returns else f"{self.method} was interrupted: {reason}"
        )

    def expire(self) -> None:
        """Its end is overdue (:data:`GRACE` past it): its call fails if unanswered."""
        self._end(f"{self.method} did not finish in time", done=False)

    @property
    def books(self) -> bool:
        """True if it holds its joints until it ends (a blocking call's task)."""
        return self.method in BOOKING

    @property
    def finished(self) -> bool:
        """True once finished or interrupted."""
        return self._done.is_set()

    def answer(self, reply: Answer) -> None:
        """Call ``reply`` once, when the task ends (now if it already has).

        With None if it finished, or was interrupted and made with
        ``killed_returns`` (a NAOqi call whose task is killed may return
        normally; the caller learns it only from when); else with the reason
        its call fails: interrupted, or never finished (:meth:`expire`).
        The first end counts: a task interrupted as the cycle finishes it
        is answered once.
        """
        with self._lock:
            outcome, self._answer = self._outcome, reply
        if outcome is not None:
            reply(outcome[0])

    def _end(self, reason: str | None, done: bool = True) -> None:
        if done:
            self._done.set()
        with self._lock:
            if self._outcome is not None:
                return
            self._outcome = (reason,)
            reply = self._answer
        if reply is not None:
            reply(reason)
