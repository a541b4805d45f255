"""What the robot's arm must be after a call: still stiff, and where it was sent.

A call that ran its whole length can still have moved nothing: an arm made
limp during it (the fall manager, the chest button, another client's
``setStiffnesses``) lets its motors go while the command plays on, and the
call ends as if all went well (a movement reported with 64 degrees of error
and no error). And an approach cut short leaves the arm away from the
trajectory's start, from where the trajectory's first key is far beyond the
speed limit. Both are checked after the call, on the robot's own word.

An arm counts as let go only below :data:`LIMP`, not below 1: the fall
manager, ``rest`` and ``setStiffnesses(..., 0)`` set the stiffness to 0,
while NAOqi's Smart Stiffness (on by default) lowers the stiffness a
still, stiff arm reports without removing it, and other clients run arms
at less than 1 on purpose (ROS's ``naoqi_dcm_driver`` at 0.9). Checked
against 0.999, every movement on such a robot failed as "dropped", and
every small sag counted as a limp arm (``bridge.limp_arm``).
"""

from __future__ import annotations

import math
import time

import numpy as np

from bridge.naoqi_client import NaoqiClient
from bridge.start_gap import START_TOLERANCE
from bridge.timeline_keys import is_hand
from shared.errors import RobotStateError

#: Less stiff than this, a joint counts as let go (limp): halfway between
#: the 0 a release sets and the 1 the bridge stiffens to, well clear of
#: what Smart Stiffness or a client holding an arm at 0.9 reads.
LIMP = 0.5
#: After an approach, the measured angles must be this close to the
#: trajectory's start [rad]: a stiff arm at rest lags its command by a
#: degree or so under gravity on a NAO, far less than a cut-short approach.
ARRIVED = math.radians(3.0)
#: Time between two readings of the stiffness that must agree [s]: a
#: release ramps (``rest`` over 0.1 s on the simulated NAO), and read at its
#: start a released arm still looks stiff.
STIFFNESS_GAP = 0.05
#: Two stiffness readings this close count as holding still.
STIFFNESS_STILL = 0.01
#: Longest wait for the stiffness to hold still [s]; then the last reading.
STIFFNESS_WAIT = 0.5


def check_still_stiff(
    client: NaoqiClient, names: list[str], chain: str, outcome: str
) -> None:
    """Raise if any of ``names`` (the arm ``chain``, e.g. ``RArm``) was let go.

    Let go: its stiffness below :data:`LIMP` (or not a number).

    Raises:
        RobotStateError: naming the chain and the least stiff joint.
    """
    stiffness = client.stiffnesses(names)
    j = int(np.argmin(stiffness))
    if not stiffness[j] >= LIMP:  # NaN too
        raise RobotStateError(
            client.url,
            f"the stiffness of {chain} dropped during the movement ({names[j]} "
            f"at {stiffness[j]:.2f}): the fall manager, a rest, or another "
            "client released it",
            outcome=outcome,
            stopped_at=time.monotonic(),
        )


def limp_joint(
    client: NaoqiClient,
    names: list[str],
    wait: float = STIFFNESS_WAIT,
    gap: float = STIFFNESS_GAP,
) -> str | None:
    """The least stiff of ``names`` if limp, e.g. ``RShoulderPitch stiffness 0.00``.

    For a call the robot ended early: the stiffness is read every ``gap``
    [s] until two readings agree within :data:`STIFFNESS_STILL` (a release
    still ramping is waited out), at most ``wait`` [s]; limp is below
    :data:`LIMP` (or not a number). None if the arm is not limp.

    Raises:
        RobotUnavailableError: the robot cannot be reached.
        RobotCommandError: the robot refused ``getStiffnesses``.
    """
    deadline = time.monotonic() + wait
    now = client.stiffnesses(names)
    while time.monotonic() < deadline:
        time.sleep(gap)
        before, now = now, client.stiffnesses(names)
        if np.abs(now - before).max() <= STIFFNESS_STILL:
            break
    j = int(np.argmin(now))
    if now[j] >= LIMP:  # NaN is limp
        return None
    return f"{names[j]} stiffness {now[j]:.2f}"


def check_at_start(client: NaoqiClient, names: list[str], start: np.ndarray) -> None:
    """Raise unless the arm is at ``start`` [rad], (n,), after an approach.

    Its command must be within ``START_TOLERANCE`` of the start and its
    measured angles within :data:`ARRIVED`: the arm's joints' only, not a
    hand's (``RHand``): a hand closed on an object reads the object's
    width, not its command, and every approach of a pick and place would
    fail.

    Raises:
        RobotStateError: naming the joint furthest off (nothing of the
            trajectory was sent).
    """
    hand = np.array([is_hand(name) for name in names], dtype=bool)
    for use_sensors, allowed in ((False, START_TOLERANCE), (True, ARRIVED)):
        where = client.get_angles(names, use_sensors=use_sensors)
        gap = np.abs(where - np.asarray(start))
        if use_sensors:  # of a hand, its command only
            gap[hand] = 0.0
        j = int(np.argmax(np.where(np.isfinite(gap), gap, np.inf)))
        if not gap[j] <= allowed:
            what = "measured" if use_sensors else "commanded"
            raise RobotStateError(
                client.url,
                f"after the approach move, {names[j]} is {what} at "
                f"{where[j]:.4f}, {math.degrees(gap[j]):.2f} deg from the "
                f"trajectory's start {start[j]:.4f} (more than "
                f"{math.degrees(allowed):.1f} deg): the approach did not arrive",
                outcome="nothing of the trajectory was sent",
            )
