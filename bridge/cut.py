"""A stopping bridge's order to stop the arm of the movement it plays.

A bridge told to stop watches the trajectory playing to its end, but only
for so long (``bridge.stopping.STOP_LIMIT``). Past that it could only leave
the robot playing on, unwatched, or stop the arm: unwatched is worse than
abrupt, so it stops the arm. :meth:`Cut.order` is given by the stop;
``bridge.playback`` looks at it between two readings and, once it is
given, stops the arm's motion tasks the way it does when it gives a robot
up (``NaoqiClient.halt``: ``ALMotion.killTasksUsingResources`` on the
arm's joints, again until the call has ended) and raises :meth:`Cut.error`.
"""

from __future__ import annotations

import threading

from shared.bus.robot_routes import BRIDGE
from shared.errors import ServiceUnavailableError


class Cut:
    """Whether the stop ordered the movement playing to be stopped, and why."""

    def __init__(self) -> None:
        self._ordered = threading.Event()
        self._why = ""

    def order(self, why: str) -> None:
        """Stop the movement playing, if any (from now on, for good).

        ``why``: why the stop cannot wait for its end, for the caller.
        """
        self._why = why
        self._ordered.set()

    @property
    def ordered(self) -> bool:
        """True once :meth:`order` was called."""
        return self._ordered.is_set()

    def error(
        self, played: float, duration: float, outcome: str
    ) -> ServiceUnavailableError:
        """The caller's error: the arm was stopped ``played`` [s] into ``duration`` [s].

        ``outcome``: what came of the stop (``NaoqiClient.halt``).
        """
        return ServiceUnavailableError(
            BRIDGE,
            reason=(
                f"the bridge is stopping; it stopped the arm at about t = "
                f"{played:.1f} s of {duration:.2f} s ({self._why}): {outcome}"
            ),
        )

    def error_on_its_way(
        self, duration: float, outcome: str
    ) -> ServiceUnavailableError:
        """The caller's error when the ``duration`` [s] call is still on its way.

        The stops follow it; the bridge exits once they have ended.
        """
        return ServiceUnavailableError(
            BRIDGE,
            reason=(
                f"the bridge is stopping; the {duration:.2f} s trajectory's call "
                f"had not reached the robot yet ({self._why}): {outcome}; the "
                "bridge exits once the stops have ended"
            ),
        )
