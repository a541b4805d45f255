"""How near a posture's palm came to the direction asked for it.

NAO's wrist has one joint, WristYaw, so the IK controls one thing about the
palm: its roll about the forearm, turned so that the palm faces the wanted
direction as well as it can. The forearm's own direction is set by the
position task (and the primitive's measure), not by the palm. With the roll
met, the palm is still off by the angle the wanted direction makes with the
plane across the forearm, up to 90 deg when the direction lies along the
forearm. This message says how far off the palm ended, so that a solved
posture never reads as "palm met" when only its roll was.
"""

from __future__ import annotations

from shared.messages.base import Direction, Message, Vec3


class PalmReached(Message):
    """The palm normal a posture reached, against the direction asked.

    Attributes:
        wanted: The palm direction asked for, unit, torso frame.
        normal: The palm normal reached, unit, torso frame (the wrist frame's
            +y axis for the right hand, -y for the left).
        angle_deg: Angle between ``normal`` and ``wanted`` [deg], 0 to 180.
            Only the roll about the forearm is controlled, so a posture the
            IK accepts can be tens of degrees off.
    """

    wanted: Direction
    normal: Vec3
    angle_deg: float
