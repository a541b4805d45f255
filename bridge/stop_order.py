"""An operator's order to stop the execution being served (``bridge/stop``).

Each execution the bridge serves carries a :class:`StopOrder`. A query on
``<ns>/bridge/stop`` orders the one being served, if any
(``BridgeService.halt``); the execution sees it at its next step: between
two readings while a movement plays (``bridge.playback``: the arm's motion
tasks are killed at once, ``NaoqiClient.halt``, as when the robot is given
up), or between two checks before the trajectory was sent
(``bridge.robot_bridge``),
and ends with the robot's usual "stopped" error
(:class:`~shared.errors.RobotStateError`, ``stopped``), saying the
``bridge/stop`` query stopped it. An order belongs to one execution: the
next one is played as usual (a stop is not a latch).
"""

from __future__ import annotations

import threading
import time

from shared.errors import RobotStateError
from shared.messages import ExecutionOutcome

#: What the outcome and error say stopped the execution.
STOPPED_BY = "bridge/stop"


class StopOrder:
    """Whether ``bridge/stop`` ordered this execution stopped; how it ended.

    Attributes:
        at: When it was ordered [s, monotonic]; None: not ordered.
        reason: The reason the query gave; None if none.
        outcome: How the execution ended, once it has (set by the bridge
            service before it frees the robot for the next one).
    """

    def __init__(self) -> None:
        self._ordered = threading.Event()
        self.at: float | None = None
        self.reason: str | None = None
        self.outcome: ExecutionOutcome | None = None

    def order(self, reason: str | None, at: float | None = None) -> None:
        """Stop the execution (the first order's time and reason are kept)."""
        if self._ordered.is_set():
            return
        self.at = time.monotonic() if at is None else at
        self.reason = reason
        self._ordered.set()

    @property
    def ordered(self) -> bool:
        """True once :meth:`order` was called."""
        return self._ordered.is_set()

    def error(
        self,
        url: str,
        outcome: str,
        *,
        phase: str | None = None,
        played: float | None = None,
        duration: float | None = None,
    ) -> RobotStateError:
        """The execution's error: stopped ``played`` [s] into its ``phase``.

        Args:
            url: The robot's address.
            outcome: What became of the movement, e.g. "the arm stopped
                where it was then (...)" (the robot confirmed it), "the stop
                was sent; the robot has not confirmed it (...)"; or
                "nothing was sent".
            phase: ``"approach"`` or ``"trajectory"``; None: between two
                movements or checks, before the trajectory was sent.
            played: Time into the phase [s], if known.
            duration: The phase's length [s].
        """
        where = (
            "the execution before its trajectory was sent"
            if phase is None
            else f"the {'approach' if phase == 'approach' else 'movement'} at "
            + (
                f"t = {played:.2f} s of {duration:.2f} s"
                if played is not None and duration is not None
                else "its start (its call had not reached the robot)"
            )
        )
        why = "" if self.reason is None else f' (reason: "{self.reason}")'
        evidence: dict[str, object] = {"stopped_by": STOPPED_BY}
        if phase is not None:
            evidence["phase"] = phase
        if played is not None:
            evidence["played"] = round(max(played, 0.0), 3)
        if duration is not None:
            evidence["duration"] = round(duration, 3)
        if self.reason is not None:
            evidence["stop_reason"] = self.reason
        return RobotStateError(
            url,
            f"a {STOPPED_BY} query stopped {where}{why}",
            outcome=outcome,
            stopped_at=self.at if self.at is not None else time.monotonic(),
            **evidence,
        )

    def check(self, url: str, outcome: str) -> None:
        """Raise the stop's error if ordered; ``outcome``: what was sent.

        Raises:
            RobotStateError: the execution was ordered stopped (``stopped``).
        """
        if self.ordered:
            raise self.error(url, outcome)
