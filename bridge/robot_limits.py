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
"""

from __future__ import annotations

from bridge.limits import FrameLimits
from bridge.naoqi_client import NaoqiClient
from shared.errors import RobotCommandError, RobotLimitsError

#: The robot's limits may be narrower than the bridge's by this much [rad,
#: rad/s]: NAOqi's limits are single precision (2.08567 comes back as
#: 2.0856685638...).
SLACK = 1e-4


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
                "lower": lower <= mine["lower"] + SLACK,
                "upper": upper >= mine["upper"] - SLACK,
                "velocity": velocity >= mine["velocity"] - SLACK,
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
