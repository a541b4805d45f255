"""A connection to a NAO's ALMotion over NAOqi (libqi), real or simulated.

Every call has a timeout and every failure becomes a typed error:
:class:`~shared.errors.RobotUnavailableError` when the robot cannot be
reached or the connection drops, :class:`~shared.errors.RobotCommandError`
when it answers but refuses. A dropped connection is closed at once; the
next call connects again, so the client picks the robot up again when it
comes back at the same address.
"""

from __future__ import annotations

import re
import threading
import time
from typing import Any

import numpy as np

from shared.errors import RobotCommandError, RobotUnavailableError
from shared.libqi import qi

#: A real NAO's NAOqi port.
NAOQI_PORT = 9559
#: Leading exception name in a libqi error text ("SimCommandError: ...").
_ERROR_NAME = re.compile(r"^\s*[A-Za-z_][\w.]*(Error|Exception): ")


#: Time between two looks at a pending libqi future [s].
POLL = 0.0005


def wait_future(future: Any, timeout: float) -> bool:
    """Wait at most ``timeout`` [s] for a libqi future; True if it finished.

    Polls ``isFinished`` instead of calling ``Future.wait``: in qi 3.1.5,
    ``wait`` can crash the process (double free) when the connection drops
    while it waits, which is exactly when the bridge must stay up.
    """
    deadline = time.monotonic() + timeout
    while not future.isFinished():
        if time.monotonic() >= deadline:
            return False
        time.sleep(POLL)
    return True


def robot_reason(error: BaseException | str) -> str:
    """The robot's own explanation from a libqi error (no traceback, no type)."""
    text = str(error).split("\n\nAt:", 1)[0].strip()
    return _ERROR_NAME.sub("", text, count=1) or "no reason given"


class NaoqiClient:
    """ALMotion of the robot at ``url``, connected on first use.

    Attributes:
        url: NAOqi address, e.g. ``tcp://127.0.0.1:9559`` (simulated NAO) or
            ``tcp://192.168.1.12:9559`` (a real one).
        connect_timeout: Longest wait for a connection [s].
        call_timeout: Longest wait for a short call's answer [s].
    """

    def __init__(
        self, url: str, *, connect_timeout: float = 2.0, call_timeout: float = 1.0
    ) -> None:
        self.url = url
        self.connect_timeout = connect_timeout
        self.call_timeout = call_timeout
        self._lock = threading.Lock()
        self._session: Any = None
        self._motion: Any = None

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
        with self._lock:
            if self._motion is None or not self.connected:
                self._reset()
                self._connect()
            return self._motion

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

    def _reset(self) -> None:
        if self._session is not None:
            self._session.close()
        self._session, self._motion = None, None

    def close(self) -> None:
        """Close the session (the next call connects again)."""
        with self._lock:
            self._reset()

    def lost(self, reason: str, elapsed: float | None = None) -> RobotUnavailableError:
        """Drop the session and return the error to raise for ``reason``."""
        self.close()
        return RobotUnavailableError(self.url, reason, elapsed=elapsed)

    def failure(
        self, method: str, error: BaseException | str, elapsed: float | None = None
    ) -> RobotUnavailableError | RobotCommandError:
        """The typed error for a failed call: lost robot, or refused command."""
        reason = robot_reason(error)
        if not self.connected:
            return self.lost(reason, elapsed)
        return RobotCommandError(self.url, method, reason)

    def call(self, method: str, *args: Any, timeout: float | None = None) -> Any:
        """Call ALMotion's ``method`` and wait at most ``timeout`` [s] for it.

        Raises:
            RobotUnavailableError: no connection, or no answer in time.
            RobotCommandError: the robot refused the command.
        """
        limit = self.call_timeout if timeout is None else timeout
        future = getattr(self.motion(), method)(*args, _async=True)
        if not wait_future(future, limit):
            future.cancel()
            raise self.lost(f"{method} got no answer within {limit:g} s")
        if future.hasError():
            raise self.failure(method, future.error())
        return future.value()

    def get_angles(self, names: list[str], use_sensors: bool = True) -> np.ndarray:
        """Angles of ``names`` [rad], measured (``use_sensors``) or commanded, (n,)."""
        return np.array(self.call("getAngles", names, use_sensors), dtype=float)

    def stiffen(self, names: list[str], duration: float = 0.2) -> bool:
        """Make ``names`` fully stiff, ramping over ``duration`` [s] if needed.

        Returns:
            Whether it ramped (False: they were stiff already).
        """
        stiffness = np.array(self.call("getStiffnesses", names), dtype=float)
        if np.all(stiffness >= 1.0):
            return False
        self.call(
            "stiffnessInterpolation",
            names,
            1.0,
            duration,
            timeout=duration + self.call_timeout,
        )
        return True

    def wait_available(self, timeout: float, poll: float = 0.2) -> bool:
        """Try to connect until it works or ``timeout`` [s] passes; True if up."""
        deadline = time.monotonic() + timeout
        while True:
            try:
                self.motion()
                return True
            except RobotUnavailableError:
                if time.monotonic() + poll > deadline:
                    return False
                time.sleep(poll)
