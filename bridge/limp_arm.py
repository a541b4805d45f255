"""A limp arm is held where it is before it is stiffened: no snap back.

With stiffness 0 a NAO's joints take commands but do not move ("at zero
stiffness, you can send any commands to the motors, but he will not move",
NAOqi's stiffness guide). An arm made limp mid-movement (the fall manager,
the chest button's rest, another client's ``setStiffnesses("RArm", 0)``)
sags or is moved by hand while its commanded angles stay where they were;
stiffened again, every motor drives to its command at full power (on the
simulated NAO, 1.17 rad at 8.8 rad/s, about four times the approach's
speed). So before the bridge stiffens a limp arm (a joint's stiffness
below ``arm_state.LIMP``, 0.5: Smart Stiffness softens a held arm, a
release sets 0), it
reads where the arm is (its sensors); if that is more than
:data:`HOLD_TOLERANCE` from the command, the command is first moved to the
measured angles, a call the limp motors do not follow, so that stiffening
holds the arm where it is and the approach starts from there. A hand
(``RHand``) is held the same way when it is limp itself: let go open, it
sags, and stiffened it snapped back to its command at its top speed (0.5
to 1.0 at 8.3 /s from standstill on the simulated NAO), arm stiff or not.
A stiff hand's command is kept: closed on an object it reads the object's
width, and its command moved there would open the grip (a limp hand grips
nothing; the approach closes it again at the approach's pace).

An arm let go falls: on a NAO for about 0.3 s. Read while falling, its
posture is one it has already fallen past by the time the command is
moved there, and stiffening drives it back up. So the sensors are read
until two readings :data:`SETTLE_GAP` apart agree within :data:`SETTLED`
(a falling arm moves far more than that); an arm still moving after
:data:`SETTLE_WAIT` is busy (:class:`~shared.errors.RobotBusyError`, "the
arm is still moving (limp, falling?)"), perhaps moved by hand.
"""

from __future__ import annotations

import math

import numpy as np

from bridge.arm_state import LIMP
from bridge.at_rest import read_angles, until_still
from bridge.limits import FrameLimits
from bridge.naoqi_client import NaoqiClient
from bridge.timeline_keys import is_hand

#: Measured and commanded angles further apart than this on an arm that is
#: limp (a joint's stiffness below ``arm_state.LIMP``): the command is
#: moved to the measured angles first [rad; open fraction for a hand].
HOLD_TOLERANCE = math.radians(0.5)
#: The command moves to the measured angles at most at this share of the
#: speed limits (the limp motors do not follow it; a motor with some
#: stiffness left is where it goes anyway).
HOLD_SPEED = 0.5
#: Shortest such move [s]: one of ALMotion's 20 ms cycles.
HOLD_SHORTEST = 0.02
#: Time between two readings of a limp arm's sensors that must agree [s].
SETTLE_GAP = 0.05
#: Two such readings this close count as an arm at rest [rad] (0.2 deg in
#: 50 ms: 4 deg/s; a NAO's encoders read to about 0.1 deg, a falling arm
#: moves tens of degrees a second).
SETTLED = math.radians(0.2)
#: Longest wait for a limp arm to come to rest [s] (a NAO's arm falls for
#: about 0.3 s).
SETTLE_WAIT = 1.0


def limp_posture(client: NaoqiClient, names: list[str]) -> np.ndarray | None:
    """Where a limp arm is [rad], (n,), if its command is elsewhere.

    Reads only: nothing is sent. The joints held are the arm's (all of
    ``names`` but a hand) if any of them is limp (its stiffness below
    ``arm_state.LIMP``: an arm Smart Stiffness has softened is not), and
    a hand that is limp itself. None if no joint is held, or the measured
    angles of those held, once at rest (:func:`settled_angles`), are within
    :data:`HOLD_TOLERANCE` of the commanded ones. Else the measured angles
    of the joints held and the commanded angles of the others (a stiff
    hand's command stays).

    Raises:
        RobotBusyError: the arm was still moving after :data:`SETTLE_WAIT`.
        RobotUnavailableError: the robot cannot be reached.
        RobotCommandError: the robot gave angles that are not numbers.
    """
    held = _limp(client, names)
    if not held:
        return None
    joints = [names[k] for k in held]
    measured = settled_angles(client, joints)
    commanded = read_angles(client, names, use_sensors=False)
    if np.abs(measured - commanded[held]).max() <= HOLD_TOLERANCE:
        return None
    where = commanded.copy()
    where[held] = measured
    return where


def _limp(client: NaoqiClient, names: list[str]) -> list[int]:
    """Indices among ``names`` of the joints to hold where they are.

    The arm's joints (all but a hand) if any of them is limp, and each hand
    that is limp itself.
    """
    stiffness = client.stiffnesses(names)
    limp = ~(stiffness >= LIMP)  # NaN counts as limp
    arm = [k for k, name in enumerate(names) if not is_hand(name)]
    arm_limp = bool(np.any(limp[arm]))
    return [k for k in range(len(names)) if limp[k] or (arm_limp and k in arm)]


def settled_angles(
    client: NaoqiClient,
    names: list[str],
    wait: float = SETTLE_WAIT,
    gap: float = SETTLE_GAP,
) -> np.ndarray:
    """The measured angles of ``names`` [rad], (n,), once they hold still.

    Read every ``gap`` [s] until two readings agree within :data:`SETTLED`.

    Raises:
        RobotBusyError: after ``wait`` [s], the arm still moved.
        RobotUnavailableError: the robot cannot be reached.
        RobotCommandError: the robot gave angles that are not numbers.
    """
    return until_still(
        client,
        names,
        use_sensors=True,
        tolerance=SETTLED,
        wait=wait,
        gap=gap,
        moving="has a limp arm whose sensors still move: "
        "the arm is still moving (limp, falling?)",
    )


def hold_command(
    client: NaoqiClient, names: list[str], where: np.ndarray, limits: FrameLimits
) -> float:
    """Move the command of ``names`` to ``where`` [rad], (n,), before stiffening.

    ``limits`` are those of ``names``, in order. The keys' single step keeps
    within :data:`HOLD_SPEED` of the speed limits from the present command.
    A joint whose ``where`` is its command (a stiff hand, from
    :func:`limp_posture`) is sent that command: it stays.

    Returns:
        The move's length [s].

    Raises:
        RobotUnavailableError: the robot cannot be reached.
        RobotCommandError: the robot refused the call.
    """
    commanded = client.get_angles(names, use_sensors=False)
    target = np.asarray(where)
    speed = HOLD_SPEED * np.asarray(limits.velocity)
    duration = max(HOLD_SHORTEST, float(np.max(np.abs(target - commanded) / speed)))
    client.call(
        "angleInterpolation",
        names,
        [[float(angle)] for angle in target],
        [[duration]] * len(names),
        True,
        timeout=duration + client.call_timeout,
    )
    return duration
