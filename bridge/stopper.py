"""Keep stopping the arm of a robot given up on until the call it was sent has ended.

``ALMotion.killTasksUsingResources`` ends the motion tasks running when the
robot serves it. A call the robot is still reading or checking is no task
yet: it starts afterwards and plays to its end. libqi sends and the robot
reads one connection's messages in order, but the robot serves them
concurrently, so a single stop sent right behind a large call is served
while the call is still being checked: on the simulated NAO the call then
played to its end 5 times in 5 for 4000 keys (3 in 5 for 2000; the
bridge's own give-up over a slow link let a 4 s movement play whole, 1.5 s
after it reported the robot stopped).

So a :class:`Stopper` keeps the given-up sessions open and, once the call
is known to have reached the robot (the arrival mark was answered, or the
stop that went behind the call was), sends the stop every control cycle on
each session still up (one stop at a time on each) until the call's own
future has finished: the robot answered the call, which has then ended,
on its own or stopped. A call that takes effect after the stops began then
moves the arm a control cycle or two (and the link's trip) before a stop
ends it. If the call's connection drops first, the robot may still hold a
call it has read: the stops go on over the other session for
:data:`SETTLE`. Everything ends at the latest after ``limit`` [s], and the
sessions are closed then.
"""

from __future__ import annotations

import threading
import time
from typing import Any

#: Time between two stops: ALMotion's control cycle [s].
PERIOD = 0.02
#: How long the stops go on after the call's connection dropped [s]: a
#: call the robot had read by then takes effect well within it (the
#: simulated NAO checks 44 000 keys in 0.1 s).
SETTLE = 1.0

#: ALMotion's method that ends the motion tasks using some joints.
STOP_METHOD = "killTasksUsingResources"


def send_stop(motion: Any, names: list[str]) -> Any:
    """The stop of ``names`` sent on ``motion`` (its libqi future), or None.

    None if ``motion`` is None or its session dropped meanwhile.
    """
    if motion is None:
        return None
    try:
        return getattr(motion, STOP_METHOD)(names, _async=True)
    except RuntimeError:  # the session dropped meanwhile
        return None


class Held:
    """A session handed to the stopper: the libqi session and its ALMotion proxy."""

    def __init__(self, session: Any, motion: Any) -> None:
        self.session, self.motion = session, motion
        self.pending: Any = None  # the last stop sent on it, a libqi future

    @property
    def up(self) -> bool:
        """True while its connection is up."""
        return bool(self.session.isConnected())

    def stop(self, names: list[str]) -> None:
        """Send a stop unless the last one is still unanswered or it is down."""
        if self.up and (self.pending is None or self.pending.isFinished()):
            self.pending = send_stop(self.motion, names) or self.pending


class Stopper:
    """Stops ``names`` on a thread until ``call`` has ended (see the module).

    Attributes:
        limit_at: When it ends at the latest [s, monotonic].
    """

    def __init__(
        self,
        call: Any,
        command: Held | None,
        watch: Held | None,
        names: list[str],
        *,
        arrived: bool,
        limit: float,
    ) -> None:
        """Start stopping.

        Args:
            call: The ``angleInterpolation`` call's libqi future.
            command: The session the call went on (its :attr:`Held.pending`:
                the stop sent behind the call), or None if it is gone.
            watch: The other session, or None.
            names: The joints whose tasks end (the arm's, as played).
            arrived: Whether the call is known to have reached the robot.
            limit: Longest time to go on [s].
        """
        self._call, self._names = call, names
        self._command, self._watch = command, watch
        self._arrived = arrived
        self._dropped: float | None = None
        self.limit_at = time.monotonic() + limit
        self._done = threading.Event()
        threading.Thread(target=self._run, name="naoqi-stopper", daemon=True).start()

    @property
    def running(self) -> bool:
        """True until it has ended and closed its sessions."""
        return not self._done.is_set()

    def wait(self, timeout: float) -> bool:
        """Wait at most ``timeout`` [s] for it to end; True if it has."""
        return self._done.wait(timeout)

    def _held(self) -> list[Held]:
        return [held for held in (self._command, self._watch) if held is not None]

    def _run(self) -> None:
        try:
            while time.monotonic() < self.limit_at and self._go_on():
                if self._arrived or self._dropped is not None:
                    for held in self._held():
                        held.stop(self._names)
                time.sleep(PERIOD)
        finally:
            for held in self._held():
                held.session.close()
            self._done.set()

    def _go_on(self) -> bool:
        """Whether the call may still start or run; notes its arrival."""
        command = self._command
        answered = self._call.isFinished()  # before looking at the connection
        if command is not None and command.up:
            if answered:
                return False  # the robot answered it: it has ended
            behind = command.pending
            if behind is not None and behind.isFinished():
                self._arrived = True  # the stop behind the call was read
            return True
        now = time.monotonic()
        if self._dropped is None:
            self._dropped = now
        return now - self._dropped < SETTLE and any(h.up for h in self._held())
