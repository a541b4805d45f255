"""A command goes out on the connection the robot was checked on, or not at all.

The bridge checks the robot before it moves it (awake: ``bridge.awake``;
its limits: ``bridge.robot_limits``) on the client's command connection.
The client connects again, silently, whenever that connection has dropped
(:class:`~bridge.naoqi_client.NaoqiClient`), and what answers at the same
address after a drop may be another robot, or the same one restarted
(perhaps no longer awake). So the bridge notes the connection's number
when it checks, and before each command that moves the arm (the hold, the
stiffening, the approach, the trajectory) refuses if the number changed:
connected again, the client must be checked again, by the next request.
"""

from __future__ import annotations

from bridge.naoqi_client import NaoqiClient
from shared.errors import RobotStateError


def check_connection(client: NaoqiClient, checked: int, outcome: str) -> None:
    """Raise unless ``client`` is still on connection ``checked``.

    Connects again first if the connection dropped (so a drop is seen
    here, not after the command has gone out on a new connection).
    ``outcome``: what was sent before.

    Raises:
        RobotStateError: the client connected again since the check.
        RobotUnavailableError: the robot cannot be reached.
    """
    client.motion()
    if client.connection != checked:
        raise RobotStateError(
            client.url,
            f"the connection to the robot was made again (connection "
            f"{client.connection}; the robot was checked on connection "
            f"{checked}): it may be another robot, or this one restarted, and "
            "it was not checked (awake, limits); send the trajectory again",
            outcome=outcome,
        )
