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
link), and a robot that is fine would look silent. When the bridge gives a
robot up (:meth:`NaoqiClient.halt`), both sessions go to a
:class:`~bridge.stopper.Stopper`, which stops the arm until the call given
up has ended; the client takes no new movement meanwhile. Its owner ends
with :meth:`NaoqiClient.shut` (or a ``with`` block), which waits for those
stops before closing: the stopper is a thread of the process, and a process
that exited under it crashed in libqi (exit 134 or 139) with the arm left
to play the call given up on.
"""

from __future__ import annotations

import logging
import threading
import time
from types import TracebackType
from typing import Any

import numpy as np

from bridge.naoqi_session import NaoqiSession
from bridge.qi_future import robot_reason, wait_future
from bridge.stopper import SETTLE, STOP_METHOD, Held, Stopper, send_stop
from shared.errors import RobotCommandError, RobotUnavailableError

log = logging.getLogger("armplan.bridge")
#: A real NAO's NAOqi port.
NAOQI_PORT = 9559

#: Longest time the bridge goes on stopping the arm of a call given up on,
#: waiting for the call to end [s].
RETIRE_AFTER = 30.0
#: How the bridge stops a robot it gives up on: every motion task using the
#: arm's joints ends (the joints hold where they are); a walk or the other
#: arm's task goes on, as ``killAll`` would not let it.
STOP = f"ALMotion.{STOP_METHOD}"


class Halted(str):
    """What :meth:`NaoqiClient.halt` came to, and whether the robot confirmed it.

    Confirmed: the robot answered the call, which has then ended (after a
    stop it answered, or before). Not: the stop was sent, or could not
    be, or was answered while the call had not arrived or not ended (a
    kill served before the call takes effect ends nothing).
    """

    confirmed: bool

    def __new__(cls, text: str, confirmed: bool) -> Halted:
        made = super().__new__(cls, text)
        made.confirmed = confirmed
        return made


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
        self._stopper: Stopper | None = None

    @property
    def connected(self) -> bool:
        """True while the command session to the robot is up."""
        return self._command.connected

    @property
    def connection(self) -> int:
        """Which connection of the command session this is (1, 2, ...).

        It changes each time the client connects again: what was learnt of
        the robot (its limits) holds for one connection only.
        """
        return self._command.generation

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

    def shut(self) -> bool:
        """Wait for the stops of a call given up on (:meth:`wait_stopped`), then close.

        What the client's owner does last, before its process exits (as the
        ``with`` block does): the stops run on a thread of this process, and
        a call still on its way would otherwise reach the robot after the
        exit and play with no one stopping it (and libqi, its callbacks
        reaching an interpreter that is finalizing, crashed the process:
        exit 134 or 139). Logs a warning if the stops outlast their bound.

        Returns:
            Whether no stopper runs any more.
        """
        stopped = self.wait_stopped()
        if not stopped:
            log.warning(
                "the bridge lets the robot go while the arm is still being "
                "stopped: a call given up on has not ended within %g s",
                RETIRE_AFTER,
            )
        self.close()
        return stopped

    def __enter__(self) -> NaoqiClient:
        return self

    def __exit__(
        self,
        kind: type[BaseException] | None,
        error: BaseException | None,
        traceback: TracebackType | None,
    ) -> None:
        self.shut()

    def lost(self, reason: str, elapsed: float | None = None) -> RobotUnavailableError:
        """Drop the sessions and return the error to raise for ``reason``."""
        self.close()
        return RobotUnavailableError(self.url, reason, elapsed=elapsed)

    def halt(self, wait: float, names: list[str], call: Any, arrived: bool) -> Halted:
        """Stop the motion tasks using ``names`` (:data:`STOP`) until ``call`` ends.

        The stop goes at once on each session still up, without connecting
        again: on the watch session it reaches the robot at once; on the
        command session it follows ``call`` if that is still on its way.
        Waits at most ``wait`` [s] for an answer (and, for a call that has
        arrived, for the call's own answer: then it has ended). A call not
        known to have ended may still start (a stop served while the robot
        is still checking the call ends nothing): both sessions are handed
        to a :class:`~bridge.stopper.Stopper`, which sends the stop every
        control cycle once the call has arrived, until the call's future has
        finished (at most :data:`RETIRE_AFTER`); until then the client
        takes no new movement (:meth:`refuse_while_stopping`).

        Args:
            wait: Longest wait for an answer [s].
            names: The joints whose tasks end (the arm's, as played).
            call: The ``angleInterpolation`` call's libqi future.
            arrived: Whether the call is known to have reached the robot.

        Returns:
            What came of it, to add to the reason the robot is given up;
            ``confirmed`` only if the call is known to have ended: the robot
            answered it (after the stop, if the call had arrived). A stop
            answered while the call had not arrived, or had not ended,
            confirms nothing: the stopper is still at work.
        """
        with self._lock:
            watch, command = self._watch.hand_over(), self._command.hand_over()
        sent = []
        for held in (watch, command):
            if held is not None:
                held.pending = send_stop(held.motion, names)
                sent.append(held.pending)
        futures = [future for future in sent if future is not None]
        if not futures:
            _close(watch, command)
            return Halted(f"no connection left to stop it ({STOP})", False)
        deadline = time.monotonic() + wait
        answered = _any_answered(futures, wait)
        if answered and arrived and command is not None:
            wait_future(call, max(0.0, deadline - time.monotonic()))
        ended = call.isFinished()  # before looking at the connection
        if ended and command is not None and command.up:
            _close(watch, command)  # the robot answered the call: it has ended
            if answered and call.hasError():
                return Halted(f"stopped it ({STOP} answered, the call ended)", True)
            return Halted("its call had ended", True)
        outcome = _stop_outcome(futures, answered, wait)
        follow = _follow_up(command is not None and command.up, arrived)
        self._stopper = Stopper(
            call, command, watch, names, arrived=arrived, limit=RETIRE_AFTER
        )
        # not confirmed, answered or not: a kill served before the call took
        # effect ends nothing, and the call is not known to have ended
        return Halted(f"{outcome}; {follow}", False)

    def wait_stopped(self) -> bool:
        """Wait until the arm is no longer being stopped after a call given up on.

        At most the stopper's own bound (:data:`RETIRE_AFTER` from its
        start). A process about to exit waits for it: the stopper is a
        thread of this process, and a call still on its way would otherwise
        reach the robot after the exit and play with no one stopping it.

        Returns:
            True if no stopper runs any more.
        """
        stopper = self._stopper
        if stopper is None or not stopper.running:
            return True
        return stopper.wait(max(0.0, stopper.limit_at - time.monotonic()) + 0.5)

    @property
    def stopping(self) -> bool:
        """True while the arm is still being stopped after a call given up on.

        (:meth:`halt`'s stopper runs: the call may still start or play.)
        """
        stopper = self._stopper
        return stopper is not None and stopper.running

    def refuse_while_stopping(self) -> None:
        """Raise if the arm is still being stopped after a call given up on.

        A movement sent meanwhile would be ended by the stops (see
        :meth:`halt`); the call given up on may still start.

        Raises:
            RobotUnavailableError: while the stops go on.
        """
        stopper = self._stopper
        if stopper is not None and stopper.running:
            left = max(0.0, stopper.limit_at - time.monotonic())
            raise RobotUnavailableError(
                self.url,
                "the bridge is still stopping the arm after giving up a call, "
                f"which has not ended (at most {left:.1f} s more); nothing was sent",
            )

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

    def stiffnesses(self, names: list[str]) -> np.ndarray:
        """Stiffnesses of ``names`` (0..1), shape (n,)."""
        return np.array(self.call("getStiffnesses", names), dtype=float)

    def stiffen(self, names: list[str], duration: float = 0.2) -> bool:
        """Make ``names`` fully stiff, ramping over ``duration`` [s] if needed.

        Returns:
            Whether it ramped (False: they were stiff already).
        """
        if np.all(self.stiffnesses(names) >= 1.0):
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


def _stop_outcome(futures: list[Any], answered: bool, wait: float) -> str:
    """What came of the stops ``futures`` (``answered``: one was, in time)."""
    if answered:
        return f"{STOP} answered"
    if all(future.isFinished() for future in futures):
        return f"{STOP} failed: {robot_reason(futures[0].error())}"
    return f"{STOP} sent, not answered within {wait:g} s"


def _follow_up(command_up: bool, arrived: bool) -> str:
    """What the stopper goes on doing, for the reason the robot is given up."""
    if not command_up:
        return (
            f"the call's connection dropped: the bridge keeps stopping the arm "
            f"for {SETTLE:g} s on the other, should the robot hold the call"
        )
    if arrived:
        return (
            "the bridge keeps stopping the arm until the call ends "
            f"(at most {RETIRE_AFTER:g} s)"
        )
    return (
        "a stop follows the call still on its way; the bridge keeps "
        f"stopping the arm until it ends (at most {RETIRE_AFTER:g} s)"
    )


def _close(*held: Held | None) -> None:
    """Close the sessions handed over."""
    for one in held:
        if one is not None:
            one.session.close()


def _any_answered(futures: list[Any], wait: float) -> bool:
    """Whether any of ``futures`` is answered without error within ``wait`` [s]."""
    deadline = time.monotonic() + wait
    return any(
        wait_future(future, max(0.0, deadline - time.monotonic()))
        and not future.hasError()
        for future in futures
    )
