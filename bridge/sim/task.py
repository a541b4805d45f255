"""A running motion command, which a blocking ALMotion call waits for."""

from __future__ import annotations

import threading

from bridge.sim.errors import SimCommandError

#: Extra time a blocking call waits past its command's end before failing [s].
GRACE = 5.0
#: The methods whose tasks book their joints, as a NAO's blocking calls do
#: (NAOqi's ``areResourcesAvailable``: "Only motion API's blocking call takes
#: resources"); ``setAngles`` and ``setStiffnesses`` book nothing.
BOOKING = frozenset(
    {"angleInterpolation", "angleInterpolationWithSpeed", "stiffnessInterpolation"}
)


class MotionTask:
    """One accepted command on a set of joints.

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
        normally instead of raising (:meth:`wait`).
        """
        self.method = method
        self.killed_returns = killed_returns
        self.start_time = start_time
        self.joints = joints
        self.end_time = end_time
        self._done = threading.Event()
        self._error: str | None = None

    def finish(self) -> None:
        """The command's joints reached their last keys."""
        self._done.set()

    def interrupt(self, reason: str) -> None:
        """Another command took its joints, or everything was stopped."""
        self._error = reason
        self._done.set()

    @property
    def books(self) -> bool:
        """True if it holds its joints until it ends (a blocking call's task)."""
        return self.method in BOOKING

    @property
    def finished(self) -> bool:
        """True once finished or interrupted."""
        return self._done.is_set()

    def wait(self, duration: float) -> None:
        """Block until done (at most ``duration`` + :data:`GRACE` [s]).

        An interrupted task raises, unless made with ``killed_returns``: then
        its call returns as if it had ended (a NAOqi call whose task is
        killed may return normally; the caller learns it only from when).

        Raises:
            SimCommandError: if it was interrupted (see above) or never
                finished.
        """
        if not self._done.wait(duration + GRACE):
            raise SimCommandError(f"{self.method} did not finish in time")
        if self._error is not None and not self.killed_returns:
            raise SimCommandError(f"{self.method} was interrupted: {self._error}")
