"""A kill's stop, as the simulated NAO logs it: measured, not hidden.

The bridge stops an arm with ``ALMotion.killTasksUsingResources`` (a
``bridge/stop``, a robot it gives up): the sim's joints then hold where
they are, a step from full speed to rest within one control cycle. Its
cycles logged only joints whose command ran, so that step left no
``state`` line: at a 5 ms cycle a stop from 3.6 rad/s measured (by
``tests.logged_motion``) 0.57 of the bridge's net acceleration, when it
was at least 8.7 times it. A measurement of the executed motion must see
every breach, the deliberate abrupt stop too (docs/robot.md).
"""

from __future__ import annotations

import contextlib
import threading
import time
from pathlib import Path

import numpy as np
from logged_motion import logged_peaks

from bridge.limits import FrameLimits
from bridge.naoqi_client import NaoqiClient
from bridge.sim import SimProcess
from bridge.sim.log import read_log

NAMES = ["RShoulderPitch"]


def test_a_kill_mid_move_logs_where_the_joint_stopped(tmp_path: Path) -> None:
    """RShoulderPitch moving 2.5 rad in 1 s is killed halfway: the log has a
    ``state`` line at the kill, and the logged motion's acceleration shows
    the stop's step, over the net; the arm is not moved again."""
    log = tmp_path / "sim.jsonl"
    with SimProcess(log_path=log, period=0.005) as sim:
        client = NaoqiClient(sim.url)
        try:
            start = float(client.call("getAngles", NAMES, True)[0])
            target = start - 2.5
            moving = threading.Thread(
                target=_ignoring_errors,
                args=(client, "angleInterpolation", NAMES, [[target]], [[1.0]], True),
            )
            moving.start()
            time.sleep(0.5)
            client.call("killTasksUsingResources", ["RArm"], timeout=5.0)
            moving.join(5.0)
            time.sleep(0.2)
        finally:
            client.close()
    entries = read_log(log)
    stopped = [e for e in entries if e["event"] == "state" and "stopped" in e]
    assert len(stopped) == 1
    assert stopped[0]["stopped"] == "killTasksUsingResources"
    held = stopped[0]["positions"]["RShoulderPitch"]
    assert target < held < start  # stopped on its way
    peaks = logged_peaks(entries, NAMES, 0.0, np.inf)
    net = FrameLimits.for_arm("right")
    assert peaks[1, 0] > 2.0 * net.acceleration[0]  # the abrupt stop, seen


def _ignoring_errors(client: NaoqiClient, method: str, *args: object) -> None:
    """``client.call(method, *args)``; the kill makes it fail, as it should."""
    with contextlib.suppress(Exception):  # the interrupted call's error
        client.call(method, *args, timeout=5.0)
