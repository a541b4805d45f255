"""The project's URDF as a ``/robot_description`` message for Foxglove.

Foxglove's 3D panel loads a robot model from a topic named exactly
``/robot_description`` whose messages carry the URDF XML in a string field
``data`` (as ROS's ``std_msgs/String``); the schema's name does not matter.
The recorder writes it once at the start of every file.
"""

from __future__ import annotations

from shared.messages import Message
from shared.robot.arm_model import urdf_text

#: The channel Foxglove's 3D panel reads the URDF from.
ROBOT_DESCRIPTION_TOPIC = "/robot_description"


class RobotDescription(Message):
    """A robot description.

    Attributes:
        data: The URDF XML text.
    """

    data: str


def robot_description() -> RobotDescription:
    """The project's URDF (``shared/robot/nao_arms.urdf``) as a message."""
    return RobotDescription(data=urdf_text())
