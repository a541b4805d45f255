"""The arm's commanded angles once it is still: no move starts from a moving arm.

An arm still moving (a command from Choregraphe or another client, or the
bridge's own movement that went on while the robot was out of reach) is
not where the bridge would count the trajectory's first step from. On a
NAO, a new ``angleInterpolation`` on joints a running motion task has
booked is postponed until that task ends (NAOqi's "Motion task" guide:
"the second one is postponed until the resource is freed"), so it would
start from wherever that movement ends, not from the angles read; a
command that books nothing (``setAngles``) is taken over at once. The
simulated NAO goes further: a new command interrupts the one on its joints
(its blocking call raises), and the arm is sent from its moving setpoint,
stopped dead and turned within one control cycle, far beyond its
acceleration and jerk limits. Either way the start is wrong, so the
commanded angles are read twice, more than two of ALMotion's 20 ms cycles
apart, and only equal readings count; and the arm's joints must be free of
every motion task (``ALMotion.areResourcesAvailable``, NAOqi 2.x): a
blocking call holds its joints until it ends, through a dwell where the
arm holds still (two equal readings), and the bridge's command would then
wait behind it on a NAO (the simulated NAO's would interrupt it).
"""

from __future__ import annotations

import time
from collections.abc import Callable

import numpy as np

from bridge.naoqi_client import NaoqiClient
from shared.errors import RobotBusyError, RobotCommandError

#: Time between two readings that must agree [s]: over two 20 ms cycles.
READ_GAP = 0.045
#: Longest wait for a moving arm to stop before refusing [s].
STILL_WAIT = 1.0
#: Readings closer than this count as equal [rad].
STILL = 1e-6


def angles_at_rest(
    client: NaoqiClient,
    names: list[str],
    wait: float = STILL_WAIT,
    gap: float = READ_GAP,
) -> np.ndarray:
    """The commanded angles of ``names`` [rad], shape (n,), once they hold still.

    Args:
        client: The robot.
        names: NAO joint names.
        wait: Longest wait for a moving arm to stop [s].
        gap: Time between readings [s].

    Raises:
        RobotBusyError: after ``wait``, the arm still moved, or a motion
            task still held its joints.
        RobotUnavailableError: the robot cannot be reached.
        RobotCommandError: the robot gave angles that are not numbers.
    """
    return until_still(
        client,
        names,
        use_sensors=False,
        tolerance=STILL,
        wait=wait,
        gap=gap,
        ready=lambda: _free(client, names),
    )


def until_still(
    client: NaoqiClient,
    names: list[str],
    *,
    use_sensors: bool,
    tolerance: float,
    wait: float,
    gap: float,
    ready: Callable[[], bool] = lambda: True,
    moving: str | None = None,
) -> np.ndarray:
    """The angles of ``names`` [rad], (n,), once two readings agree.

    Read every ``gap`` [s] (commanded, or measured with ``use_sensors``)
    until two in a row agree within ``tolerance`` [rad] and ``ready()``.

    Raises:
        RobotBusyError: after ``wait`` [s] they still did not (``moving``:
            how the error says the arm moves; default the bridge's own).
        RobotUnavailableError: the robot cannot be reached.
        RobotCommandError: the robot gave angles that are not numbers.
    """
    deadline = time.monotonic() + wait
    before = read_angles(client, names, use_sensors)
    while True:
        time.sleep(gap)
        now = read_angles(client, names, use_sensors)
        if np.abs(now - before).max() <= tolerance and ready():
            return now
        if time.monotonic() >= deadline:
            raise RobotBusyError(client.url, None, moving=moving)
        before = now


def _free(client: NaoqiClient, names: list[str]) -> bool:
    """Whether no motion task holds any of ``names`` (``areResourcesAvailable``)."""
    return bool(client.call("areResourcesAvailable", names))


def read_angles(client: NaoqiClient, names: list[str], use_sensors: bool) -> np.ndarray:
    """The commanded (or measured) angles [rad], (n,); finite, or RobotCommandError."""
    angles = client.get_angles(names, use_sensors=use_sensors)
    if not np.all(np.isfinite(angles)):
        raise RobotCommandError(
            client.url, "getAngles", f"it gave angles that are not numbers: {angles}"
        )
    return angles
