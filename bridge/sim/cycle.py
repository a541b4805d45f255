"""ALMotion's control cycle: a thread that steps the simulated robot every 20 ms."""

from __future__ import annotations

import math
import threading
import time

from bridge.sim.robot import SimRobot
from shared.errors import InvalidInputError

#: ALMotion's documented control cycle [s].
PERIOD = 0.02
#: Shortest and longest control cycle a simulated NAO may run [s].
SHORTEST, LONGEST = 0.001, 1.0


def check_period(period: float) -> float:
    """``period`` [s] if within ``SHORTEST``..``LONGEST``; else InvalidInputError."""
    if not SHORTEST <= period <= LONGEST:  # NaN fails too
        raise InvalidInputError(
            f"control cycle {period} s must be {SHORTEST:g}..{LONGEST:g} s "
            f"(ALMotion's is {PERIOD:g} s)",
            field="period",
        )
    return period


class ControlCycle:
    """Calls ``robot.step()`` every ``period`` seconds on its own thread.

    The schedule is absolute (cycle k at start + k * period). A cycle that
    comes late runs once, late, and the next one waits for the next slot of
    the schedule: the missed slots are skipped, not run back to back.
    """

    def __init__(self, robot: SimRobot, period: float = PERIOD) -> None:
        self.period = check_period(period)
        self._robot = robot
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._run, name="sim-cycle", daemon=True)

    def start(self) -> None:
        """Start cycling."""
        self._thread.start()

    def stop(self, timeout: float = 2.0) -> None:
        """Stop cycling and wait for the thread (at most ``timeout`` [s]).

        Safe before :meth:`start` (nothing to wait for): a sim that failed to
        listen stops its cycle on the way out without a second error.
        """
        self._stop.set()
        if self._thread.ident is not None:
            self._thread.join(timeout)

    def _run(self) -> None:
        next_time = time.monotonic()
        while not self._stop.is_set():
            self._robot.step()
            next_time = next_slot(next_time, self.period, time.monotonic())
            self._stop.wait(max(0.0, next_time - time.monotonic()))


def next_slot(last: float, period: float, now: float) -> float:
    """The first slot ``last + k * period`` (k >= 1) after ``now`` [s]."""
    slot = last + (max(0, math.floor((now - last) / period)) + 1) * period
    return slot + period if slot <= now else slot  # the division's rounding
