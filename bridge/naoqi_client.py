"""A connection to a NAO's ALMotion over NAOqi (libqi), real or simulated.

Every call has a timeout and every failure becomes a typed error:
:class:`~shared.errors.RobotUnavailableError` when the robot cannot be
reached or the connection drops, :class:`~shared.errors.RobotCommandError`
when it answers but refuses. A dropped connection is closed at once; the
next call connects again, so the client picks the robot up again when it
comes back at the same address.

The client holds two libqi sessions, each its own TCP connection: the
*command* session carries the calls (:meth:`NaoqiClient.motion`), the
*watch* session the readings taken while a movement plays
(:meth:`NaoqiClient.watch`). On one connection a reading waits behind a
long call still on its way (1500 frames take over a second over a 200 kB/s
link), and a robot that is fine would look silent.
"""

from __future__ import annotations

import threading
import time
from typing import Any

import numpy as np

from bridge.naoqi_session import NaoqiSession
from bridge.qi_future import robot_reason, wait_future
from shared.errors import RobotCommandError, RobotUnavailableError

#: A real NAO's NAOqi port.
NAOQI_PORT = 9559

#: Longest time a session is kept open for a stop still on its way [s].
RETIRE_AFTER = 30.0
#: How the bridge stops a robot it gives up on: every motion task using the
#: arm's joints ends (the joints hold where they are); a walk or the other
#: arm's task goes on, as ``killAll`` would not let it.
STOP = "ALMotion.killTasksUsingResources"


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
        self._command = NaoqiSession(url, connect_timeout)
        self._watch = NaoqiSession(url, connect_timeout)

    @property
    def connected(self) -> bool:
        """True while the command session to the robot is up."""
        return self._command.connected

    @property
    def watching(self) -> bool:
        """True while the watch session (the readings') is up."""
        return self._watch.connected

    def motion(self) -> Any:
        """The ALMotion proxy of the command session, connecting first if needed.

        Raises:
            RobotUnavailableError: if the robot cannot be reached in time or
                serves no ALMotion.
        """
        with self._lock:
            return self._command.motion()

    def watch(self) -> Any:
        """The ALMotion proxy of the watch session, connecting first if needed.

        Readings on it never wait behind a call on the command session.

        Raises:
            RobotUnavailableError: if the robot cannot be reached in time or
                serves no ALMotion.
        """
        with self._lock:
            return self._watch.motion()

    def close(self) -> None:
        """Close both sessions (the next call connects again)."""
        with self._lock:
            self._command.close()
            self._watch.close()

    def lost(self, reason: str, elapsed: float | None = None) -> RobotUnavailableError:
        """Drop the sessions and return the error to raise for ``reason``."""
        self.close()
        return RobotUnavailableError(self.url, reason, elapsed=elapsed)

    def halt(self, wait: float, names: list[str], on_its_way: bool = False) -> str:
        """Ask the robot to end the motion tasks using ``names`` (:data:`STOP`).

        Sent on each session still up, without connecting again: on the
        watch session it reaches the robot at once; on the command session
        it follows any call still on its way there, so it ends that call as
        it arrives. Waits at most ``wait`` [s] for an answer; a command
        session whose stop is still unanswered is then retired (closed
        once it is answered, at most :data:`RETIRE_AFTER` later), not closed
        at once, which would drop it but not the call before it.

        Args:
            wait: Longest wait for an answer [s].
            names: The joints whose tasks end (the arm's, as played).
            on_its_way: Whether a call on the command session has not yet
                reached the robot (for the text returned).

        Returns:
            What came of it, to add to the reason the robot is given up.
        """
        with self._lock:
            watch, command = self._watch.proxy(), self._command.proxy()
        sent = [_stop(watch, names), _stop(command, names)]
        futures = [future for future in sent if future is not None]
        if not futures:
            return f"no connection left to stop it ({STOP})"
        stopped = _any_answered(futures, wait)
        behind = sent[1] is not None and not sent[1].isFinished()
        if behind:
            with self._lock:
                self._command.retire(sent[1], RETIRE_AFTER)
        if stopped:
            outcome = f"stopped it ({STOP} answered)"
        elif all(future.isFinished() for future in futures):
            outcome = f"{STOP} failed: {robot_reason(futures[0].error())}"
        else:
            outcome = f"{STOP} sent, not answered within {wait:g} s"
        if behind and on_its_way:
            outcome += (
                "; another, behind the call still on its way, ends it if it arrives"
            )
        return outcome

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


def _stop(motion: Any, names: list[str]) -> Any:
    """:data:`STOP` of ``names`` sent (its libqi future), or None if it cannot be."""
    if motion is None:
        return None
    try:
        return motion.killTasksUsingResources(names, _async=True)
    except RuntimeError:  # the session dropped meanwhile
        return None


def _any_answered(futures: list[Any], wait: float) -> bool:
    """Whether any of ``futures`` is answered without error within ``wait`` [s]."""
    deadline = time.monotonic() + wait
    return any(
        wait_future(future, max(0.0, deadline - time.monotonic()))
        and not future.hasError()
        for future in futures
    )
