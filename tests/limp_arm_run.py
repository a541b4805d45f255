"""A limp, sagged right arm on the simulated NAO, and its speeds measured.

The exported scripts (``play.py``, the Choregraphe start box) must hold a
limp arm where it hangs before they stiffen it. Their tests share this
set-up: the arm is held at a posture, let go so it sags, and the sensors
are sampled every 5 ms while the script runs.
"""

from __future__ import annotations

import threading
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np

#: Time the let-go arm is given to sag and settle [s].
SAG_TIME = 1.0

#: Gap between two sensor readings while a script runs [s].
SAMPLE_GAP = 0.005

#: Control cycle the readings are resampled on [s] (NAO's ALMotion cycle).
CYCLE = 0.02


@dataclass
class LimpArm:
    """A right arm let go at ``held`` on a simulated NAO.

    Attributes:
        motion: the ALMotion proxy of a session on the simulated NAO.
        names: the arm's joint names, shape (n,).
        hangs: where the limp arm hangs [rad], shape (n,).
        samples: (monotonic time [s], sensed angles [rad]) readings taken
            while :meth:`sampled` ran.
    """

    motion: Any
    names: list[str]
    hangs: np.ndarray
    samples: list[tuple[float, list[float]]] = field(default_factory=list)

    def sampled(self, run: Callable[[], Any]) -> Any:
        """Run ``run()`` while the sensors are read every SAMPLE_GAP; its result."""
        done = threading.Event()

        def sample() -> None:
            while not done.is_set():
                self.samples.append(
                    (time.monotonic(), self.motion.getAngles(self.names, True))
                )
                time.sleep(SAMPLE_GAP)

        sampler = threading.Thread(target=sample)
        sampler.start()
        try:
            return run()
        finally:
            done.set()
            sampler.join()

    def fastest(self) -> np.ndarray:
        """Each joint's fastest measured speed [rad/s], shape (n,): the
        readings resampled every control cycle (CYCLE)."""
        t = np.array([s[0] for s in self.samples])
        q = np.array([s[1] for s in self.samples])
        grid = np.arange(t[0], t[-1], CYCLE)
        cycles = np.column_stack(
            [np.interp(grid, t, q[:, j]) for j in range(q.shape[1])]
        )
        return np.asarray(np.abs(np.diff(cycles, axis=0) / CYCLE).max(axis=0))


def let_go(session: Any, names: list[str], held: Any) -> LimpArm:
    """Hold the right arm at ``held`` [rad], let it go and wait SAG_TIME.

    ``session`` is a connected ``qi.Session`` on a simulated NAO started
    with ``limp_sag``; ``names`` are the arm's joints, in ``held``'s order.
    """
    motion = session.service("ALMotion")
    motion.angleInterpolationWithSpeed(names, np.asarray(held).tolist(), 0.2)
    motion.setStiffnesses("RArm", 0.0)
    time.sleep(SAG_TIME)
    return LimpArm(motion, names, np.array(motion.getAngles(names, True)))
