"""The request a bridge serves: what it has sent, and when its movement ends.

One robot plays one trajectory at a time. A request takes the
:class:`Slot` before it is checked against the robot and gives it back
when it is answered; meanwhile :class:`Serving` says what it has sent
(nothing yet, its approach, its trajectory) and when its movement ends,
about: the refused caller is told how long is left, and a bridge told to
stop waits that long (``BridgeService.stop``). The slot and what the
request has sent change together, under one lock, so a stop never sees a
request that holds the slot with its predecessor's end time.

A trajectory ends its duration after its call has *reached* the robot
(the robot counts its keys from then), which, for a large call over a slow
link, is seconds after it left: the end is counted from the call's
arrival (``bridge.playback``'s arrival mark) once that is known. While
the call is on its way, the trajectory ends no sooner than its duration
from now, and no later than ``playback`` waits for it: arrived within its
duration + ``OVERRUN`` of leaving, then its duration.

Each request carries its :class:`~bridge.stop_order.StopOrder`: an
operator's ``bridge/stop`` orders the one holding the slot (:meth:`Slot.halt`),
under the same lock, so it never stops the next request instead. A
follower's trajectory, or an execute query, that arrived before a stop is
stopped as it takes the slot (``since``): the stop meant it too.
"""

from __future__ import annotations

import threading
import time
from collections.abc import Callable
from dataclasses import dataclass, field, replace

from bridge.playback import OVERRUN
from bridge.stop_order import StopOrder


@dataclass(frozen=True)
class Serving:
    """What the request being served has done.

    Attributes:
        duration: The trajectory's duration [s].
        ends: When its movement ends, about [s, monotonic]; while its call
            is on its way, see :meth:`end`.
        moving: Whether a movement was sent (its approach or trajectory).
        sent: When the trajectory's call left [s, monotonic]; None: not yet.
        arrival: When it reached the robot [s, monotonic]; None: not yet.
        order: Its order to stop (``bridge/stop``).
        arm: The arm it moves, ``"right"`` or ``"left"``; None: not said.
    """

    duration: float
    ends: float
    moving: bool = False
    sent: float | None = None
    arrival: float | None = None
    order: StopOrder = field(default_factory=StopOrder)
    arm: str | None = None

    def end(self, now: float) -> float:
        """When the movement ends, about [s, monotonic], as seen at ``now``."""
        if self.sent is None or self.arrival is not None:
            return self.ends
        latest = self.sent + self.duration + OVERRUN + self.duration
        return min(max(self.ends, now + self.duration), latest)


class Slot:
    """The one request a robot serves at a time, and what it has done."""

    def __init__(self) -> None:
        self._changed = threading.Condition()
        self._serving: Serving | None = None
        self._last_stop = -float("inf")  # [s, monotonic]: the last halt's
        self._last_reason: str | None = None  # its reason

    def take(
        self,
        duration: float,
        wait: bool,
        order: StopOrder | None = None,
        since: float | None = None,
        arm: str | None = None,
    ) -> bool:
        """Take the slot for a trajectory of ``duration`` [s]; False if busy.

        Args:
            duration: The trajectory's length [s].
            wait: Wait for the request being served to end instead.
            order: The request's order to stop; None: one of its own.
            since: When its request arrived [s, monotonic] (the follower's
                trajectory, an execute query); a :meth:`halt` after that
                orders it stopped now. None: only a halt from now on stops
                it.
            arm: The arm it moves (what a stop says it stopped).
        """
        order = StopOrder() if order is None else order
        with self._changed:
            if self._serving is not None and not wait:
                return False
            self._changed.wait_for(lambda: self._serving is None)
            if since is not None and since <= self._last_stop:
                order.order(self._last_reason, self._last_stop)
            self._serving = Serving(
                duration, time.monotonic() + duration, order=order, arm=arm
            )
            return True

    def halt(self, reason: str | None, at: float) -> Serving | None:
        """Order the request being served stopped (``bridge/stop`` at ``at``).

        Returns:
            What it had done when ordered; None if no request was served.
        """
        with self._changed:
            if at >= self._last_stop:
                self._last_stop, self._last_reason = at, reason
            serving = self._serving
            if serving is not None:
                serving.order.order(reason, at)
            return serving

    @property
    def serving(self) -> Serving | None:
        """What the request being served has done; None: none is."""
        with self._changed:
            return self._serving

    def give_back(self) -> None:
        """The request has been answered."""
        with self._changed:
            self._serving = None
            self._changed.notify_all()

    def left(self) -> float:
        """About how long the movement being served has left [s] (0: none)."""
        with self._changed:
            serving, now = self._serving, time.monotonic()
            return 0.0 if serving is None else max(serving.end(now) - now, 0.0)

    def approaching(self, approach: float) -> None:
        """The approach, ``approach`` [s] long, is sent: the trajectory follows."""
        ends = time.monotonic() + approach

        self._change(lambda s: replace(s, ends=ends + s.duration, moving=True))

    def sending(self) -> None:
        """The trajectory's call leaves now."""
        now = time.monotonic()
        self._change(lambda s: replace(s, ends=now + s.duration, moving=True, sent=now))

    def arrived(self, at: float) -> None:
        """The trajectory's call reached the robot at ``at`` [s, monotonic]."""
        self._change(lambda s: replace(s, ends=at + s.duration, arrival=at))

    def _change(self, change: Callable[[Serving], Serving]) -> None:
        with self._changed:
            if self._serving is not None:
                self._serving = change(self._serving)
            self._changed.notify_all()

    def wait_free(
        self,
        deadline: Callable[[Serving, float], float],
        poll: float = 0.1,
        gone: StopOrder | None = None,
    ) -> Serving | None:
        """Wait for the slot to be free, at most until ``deadline``.

        Args:
            deadline: When to stop waiting [s, monotonic], given what the
                request does and the time [s, monotonic]; asked again at
                each change, and every ``poll`` [s].
            poll: Longest time between two looks [s].
            gone: Wait only for the request of this order to give the
                slot back: a request not ordered stopped that took it then
                (the follower's next trajectory) ends the wait too.

        Returns:
            None if the slot is free; else what the request holding it has
            done (at the deadline, or the new one holding it).
        """
        with self._changed:
            while self._serving is not None:
                serving = self._serving
                new = gone is not None and serving.order is not gone
                if new and not serving.order.ordered:  # the next, not stopped
                    return serving
                now = time.monotonic()
                left = deadline(self._serving, now) - now
                if left <= 0.0:
                    return self._serving
                self._changed.wait(min(left, poll))
            return None
