"""Play an ``angleInterpolation`` call and sample the measured angles meanwhile.

The call runs asynchronously; while it runs, ``getAngles(names, True)`` is
read every ``period`` seconds, on a fixed schedule from the call's start
(``next_reading``), so a reading's round trip does not stretch the period. A
sample's time is the middle of its request and its answer, counted from the
moment the call left (after libqi converted its arguments); it is uncertain
by half the round trip, which is kept with the sample.

The robot counts the keys from when it has received the call, which can be
well after the call left: a long call at a high frame rate is a large
message to carry and to parse (libqi sends 16 bytes a key, 240 kB for 1500
frames of five joints; 44 000 frames began on the simulated NAO 0.5-0.7 s
after they left, over loopback). ``angleInterpolation`` answers when the
movement ends, the call's duration after the robot began it, so the
answer's arrival less that duration is when the robot began, at the latest
(early by the answer's own trip and up to a control cycle). How long after
the call left that was is kept with the samples (``start_delay``).

If the robot drops the connection, stops answering for ``LOST_AFTER``
seconds, or overruns the call's duration, the robot is declared lost with a
:class:`~shared.errors.RobotUnavailableError`.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from typing import Any, NamedTuple

import numpy as np

from bridge.almotion import AngleInterpolationCall
from bridge.naoqi_client import NaoqiClient, wait_future
from shared.messages import JointState

#: Time between two readings of the measured angles [s] (100 Hz).
SAMPLE_PERIOD = 0.01
#: A robot that answers no reading for this long is lost [s].
LOST_AFTER = 1.0
#: Time allowed past the call's last key before the robot is declared lost [s].
OVERRUN = 1.0


class Samples(NamedTuple):
    """Measured angles during a call.

    Attributes:
        times: Sample times from the call's start [s], shape (k,).
        positions: Measured angles [rad], shape (k, n).
        round_trips: Time from each request to its answer [s], shape (k,);
            a sample's time is uncertain by half of it. ``None``: exact times.
        start_delay: How long after the call left the robot began it, at
            most [s]: its answer came this much later than the call's
            duration after it left (0 if not later).
    """

    times: np.ndarray
    positions: np.ndarray
    round_trips: np.ndarray | None = None
    start_delay: float = 0.0


class _Reader:
    """Reads the measured angles of ``names`` with a timeout."""

    def __init__(self, motion: Any, names: list[str], timeout: float) -> None:
        self.motion, self.names, self.timeout = motion, names, timeout

    def read(self) -> tuple[float, float, list[float] | None, str]:
        """(time [s, monotonic], round trip [s], angles or None, error text)."""
        sent = time.monotonic()
        future = self.motion.getAngles(self.names, True, _async=True)
        finished = wait_future(future, self.timeout)
        answered = time.monotonic()
        if not finished:
            future.cancel()
            return answered, answered - sent, None, "no answer to getAngles"
        if future.hasError():
            return answered, answered - sent, None, future.error()
        return 0.5 * (sent + answered), answered - sent, list(future.value()), ""


def next_reading(due: float, period: float, now: float) -> float:
    """When to read next [s, monotonic]: one ``period`` [s] after ``due``.

    Readings keep to a fixed schedule, so the rate is ``1 / period`` however
    long each round trip takes (waiting ``period`` after each answer made
    93.7 Hz of 100). A reading that falls a whole period or more behind
    (a slow answer) does not bring a burst of catch-up readings: the
    schedule starts again from ``now``.
    """
    due += period
    return due if due > now - period else now


def play_and_sample(
    client: NaoqiClient,
    call: AngleInterpolationCall,
    *,
    period: float = SAMPLE_PERIOD,
    on_sample: Callable[[JointState], None] | None = None,
) -> Samples:
    """Send ``call`` and sample the measured angles until it ends.

    Args:
        client: The robot.
        call: The ``angleInterpolation`` arguments.
        period: Time between readings [s].
        on_sample: Called with each measured state (e.g. to publish it).

    Raises:
        RobotUnavailableError: the robot went away during the call (within
            :data:`LOST_AFTER` seconds of it going).
        RobotCommandError: the robot refused the call.
    """
    motion = client.motion()
    reader = _Reader(motion, call.names, min(period * 20, LOST_AFTER / 2))
    future = motion.angleInterpolation(*call, _async=True)
    # The samples' clock starts when the call leaves, after libqi has
    # converted its arguments (milliseconds for a long trajectory), not before.
    start = time.monotonic()
    answered: list[float] = []  # stamped on libqi's thread, not at the next poll
    future.addCallback(lambda _: answered.append(time.monotonic()))
    times: list[float] = []
    rows: list[list[float]] = []
    round_trips: list[float] = []
    last_answer = due = start
    while not future.isFinished():
        stamp, round_trip, angles, problem = reader.read()
        elapsed = stamp - start
        if angles is not None:
            last_answer = stamp
            times.append(elapsed)
            rows.append(angles)
            round_trips.append(round_trip)
            if on_sample is not None:
                on_sample(
                    JointState(time=elapsed, joint_names=call.names, positions=angles)
                )
        elif not client.connected or stamp - last_answer > LOST_AFTER:
            future.cancel()
            raise client.lost(problem, elapsed)
        if elapsed > call.duration + OVERRUN:
            future.cancel()
            raise client.lost(
                f"the movement did not end {OVERRUN:g} s after its last key", elapsed
            )
        due = next_reading(due, period, time.monotonic())
        time.sleep(max(0.0, due - time.monotonic()))
    seen = time.monotonic()
    if future.hasError():
        raise client.failure(
            "angleInterpolation", future.error(), time.monotonic() - start
        )
    width = len(call.names)
    end = min([seen, *answered])  # the callback may not have run yet
    return Samples(
        np.array(times),
        np.array(rows, dtype=float).reshape(-1, width),
        np.array(round_trips),
        max(0.0, end - start - call.duration),
    )
