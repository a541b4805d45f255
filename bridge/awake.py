"""The robot must be awake before its arm moves.

A NAO at rest (after ``ALMotion.rest()``, at boot, or laid down by the fall
manager) is crouching or lying with its joints limp; stiffening one arm and
playing a reach there swings it into the floor, the table or the robot's
own legs. ``ALMotion.robotIsWakeUp()`` says whether it is awake: if not,
the bridge refuses before sending anything, unless told otherwise
(``--allow-not-awake`` on the bridge's command line, for a robot held up by
other means).
"""

from __future__ import annotations

from bridge.naoqi_client import NaoqiClient
from shared.errors import RobotStateError

#: The bridge's command-line option that lets it play on a robot not awake.
ALLOW_NOT_AWAKE = "--allow-not-awake"


def check_awake(client: NaoqiClient) -> None:
    """Raise unless ``ALMotion.robotIsWakeUp()`` is true.

    Raises:
        RobotStateError: the robot is not awake (nothing was sent).
        RobotUnavailableError: the robot cannot be reached.
        RobotCommandError: the robot refused the call.
    """
    if not bool(client.call("robotIsWakeUp")):
        raise RobotStateError(
            client.url,
            "the robot is not awake (ALMotion.robotIsWakeUp() is false): wake it "
            f"and stand it first (or start the bridge with {ALLOW_NOT_AWAKE})",
            outcome="nothing was sent",
        )
