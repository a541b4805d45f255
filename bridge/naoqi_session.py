"""One libqi session to a NAO's ALMotion: its own TCP connection.

libqi carries a session's messages in order on one connection, so a small
call sent after a large one waits until the large one has arrived: the
bridge reads the measured angles on a session of their own
(:class:`~bridge.naoqi_client.NaoqiClient` holds two), so that a long
``angleInterpolation`` on its way to the robot does not hold them up.
"""

from __future__ import annotations

from typing import Any

from bridge.qi_future import robot_reason, wait_future
from bridge.stopper import Held
from shared.errors import RobotUnavailableError
from shared.libqi import qi


class NaoqiSession:
    """A libqi session to ``url`` and its ALMotion proxy, connected on demand.

    Not thread-safe: :class:`~bridge.naoqi_client.NaoqiClient` locks around
    :meth:`motion` and :meth:`close`.
    """

    def __init__(self, url: str, connect_timeout: float) -> None:
        """Describe the session; nothing connects yet.

        Args:
            url: NAOqi address, e.g. ``tcp://127.0.0.1:9559``.
            connect_timeout: Longest wait for the connection [s].
        """
        self.url = url
        self.connect_timeout = connect_timeout
        self._session: Any = None
        self._motion: Any = None
        #: Counts the connections made; a new one may be another robot.
        self.generation = 0

    @property
    def connected(self) -> bool:
        """True while the session to the robot is up."""
        session = self._session
        return session is not None and bool(session.isConnected())

    def motion(self) -> Any:
        """The ALMotion proxy, connecting (again) first if needed.

        Raises:
            RobotUnavailableError: if the robot cannot be reached in time or
                serves no ALMotion.
        """
        if self._motion is None or not self.connected:
            self.close()
            self._connect()
        return self._motion

    def proxy(self) -> Any:
        """The ALMotion proxy if the session is up, else None (no connecting)."""
        return self._motion if self.connected else None

    def _connect(self) -> None:
        session = qi.Session()
        future = session.connect(self.url, _async=True)
        finished = wait_future(future, self.connect_timeout)
        if not finished or future.hasError():
            reason = (
                robot_reason(future.error())
                if finished
                else f"no answer within {self.connect_timeout:g} s"
            )
            future.cancel()
            session.close()
            raise RobotUnavailableError(self.url, reason)
        try:
            self._motion = session.service("ALMotion")
        except RuntimeError as error:
            session.close()
            raise RobotUnavailableError(
                self.url, f"no ALMotion service: {robot_reason(error)}"
            ) from None
        self._session = session
        self.generation += 1

    def close(self) -> None:
        """Close the session (the next :meth:`motion` connects again)."""
        if self._session is not None:
            self._session.close()
        self._session, self._motion = None, None

    def hand_over(self) -> Held | None:
        """Let go of the session for a :class:`~bridge.stopper.Stopper` to close.

        Returns the session and its proxy if it is up (else None, closing
        it); the next :meth:`motion` opens a new one. Closing it at once
        would drop what is still on its way on it, a stop behind a long
        call, but not the call, already in the kernel's buffers, which then
        arrived and played.
        """
        session, motion = self._session, self._motion
        self._session, self._motion = None, None
        if session is None:
            return None
        if not session.isConnected():
            session.close()
            return None
        return Held(session, motion)
