"""The robot's own joint limits must not be narrower than the bridge's.

The bridge checks every frame against its limits, the robot description's
(a NAO H25 V5/V6). Another robot (a Pepper's shoulder and elbow rolls stop
short of a NAO's), or a NAO whose limits were changed, would be sent frames
it cannot follow. So the bridge asks the robot, ``ALMotion.getLimits(name)``
per joint, which NAOqi answers ``[[min angle, max angle, max velocity,
max torque]]`` [rad, rad, rad/s, N m], and refuses if a range or a speed
limit of a joint it moves is narrower than its own. The answers hold for
one connection: after connecting again (perhaps to another robot) they are
asked again.

Narrower means by more than rounding (:func:`slack`): the bridge's limits
are the robot description's, written to :data:`DIGITS` significant digits
(RElbowRoll's 1.54462 for NAOqi's 88.5 degrees, 1.5446164 rad; ShoulderPitch's
2.08567 for 119.5 degrees, which NAOqi answers in single precision as
2.0856685638...), and NAOqi's are single precision. A fixed 1e-4 let a
robot whose RElbowRoll stopped at 1.54453 through, and it refused the
bridge's key at 1.54462.
"""

from __future__ import annotations

import math

import numpy as np

from bridge.limits import FrameLimits
from bridge.naoqi_client import NaoqiClient
from shared.errors import RobotCommandError, RobotLimitsError

#: Significant digits of the robot description's limits (``nao_arms.urdf``).
DIGITS = 6
#: Single-precision steps (ULPs, at the limit's magnitude) a robot's limit
#: may be off by, besides the description's rounding.
FLOAT32_STEPS = 4


def slack(value: float) -> float:
    """How much narrower than the bridge's ``value`` a robot's limit may be.

    Half a unit in the :data:`DIGITS`-th significant digit of ``value`` (the
    description's rounding: 5e-6 at 1.54462) plus :data:`FLOAT32_STEPS`
    single-precision steps at its magnitude (4.8e-7 there) [rad, rad/s].
    """
    size = abs(value)
    steps = FLOAT32_STEPS * float(np.spacing(np.float32(size)))
    if size == 0.0 or not math.isfinite(size):
        return steps
    return 0.5 * 10.0 ** (math.floor(math.log10(size)) - DIGITS + 1) + steps


class RobotLimitsCheck:
    """Compares the robot's limits with the bridge's, once per joint and connection."""

    def __init__(self) -> None:
        self._connection = -1
        self._checked: set[str] = set()

    def check(self, client: NaoqiClient, limits: FrameLimits) -> None:
        """Raise if the robot allows any joint of ``limits`` less than they do.

        Raises:
            RobotLimitsError: naming the joint, the limit and both values
                (nothing was sent).
            RobotUnavailableError: the robot cannot be reached.
            RobotCommandError: the robot refused ``getLimits`` or gave no
                four numbers.
        """
        client.motion()  # connected first: the connection's number is its own
        if client.connection != self._connection:
            self._connection, self._checked = client.connection, set()
        for j, name in enumerate(limits.names):
            if name in self._checked:
                continue
            lower, upper, velocity = _robot_limits(client, name)
            mine = {
                "lower": float(limits.lower[j]),
                "upper": float(limits.upper[j]),
                "velocity": float(limits.velocity[j]),
            }
            fits = {
                "lower": lower <= mine["lower"] + slack(mine["lower"]),
                "upper": upper >= mine["upper"] - slack(mine["upper"]),
                "velocity": velocity >= mine["velocity"] - slack(mine["velocity"]),
            }
            robot = {"lower": lower, "upper": upper, "velocity": velocity}
            for quantity, ok in fits.items():
                if not ok:  # a NaN fails too
                    raise RobotLimitsError(
                        client.url, name, quantity, robot[quantity], mine[quantity]
                    )
            self._checked.add(name)


def _robot_limits(client: NaoqiClient, name: str) -> tuple[float, float, float]:
    """The robot's (min angle, max angle, max velocity) of joint ``name``."""
    answer = client.call("getLimits", name)
    try:
        row = [float(value) for value in answer[0]]
        return row[0], row[1], row[2]
    except (TypeError, ValueError, IndexError):
        raise RobotCommandError(
            client.url, "getLimits", f"it gave {answer!r} for {name}, not 4 numbers"
        ) from None
