"""Which arm: the ``Side`` enum and the NAO joint names that go with it."""

from __future__ import annotations

from enum import StrEnum
from typing import Annotated

from pydantic import BeforeValidator

from shared.errors import UnknownArmError

#: The five arm joints in the paper's order ("joint 1..5"), without side prefix.
JOINTS: tuple[str, ...] = (
    "ShoulderPitch",
    "ShoulderRoll",
    "ElbowYaw",
    "ElbowRoll",
    "WristYaw",
)


class Side(StrEnum):
    """An arm of NAO. The value is the name used on the command line and wire."""

    RIGHT = "right"
    LEFT = "left"

    @classmethod
    def parse(cls, name: str | Side) -> Side:
        """Side from ``"right"``/``"left"`` (any case); raises ``UnknownArmError``."""
        if isinstance(name, Side):
            return name
        try:
            return cls(str(name).strip().lower())
        except ValueError:
            raise UnknownArmError(str(name)) from None

    @property
    def prefix(self) -> str:
        """NAO's joint-name prefix: ``"R"`` or ``"L"``."""
        return "R" if self is Side.RIGHT else "L"

    @property
    def sign(self) -> float:
        """+1 for the right arm, -1 for the left: mirrors y and the roll/yaw joints."""
        return 1.0 if self is Side.RIGHT else -1.0

    @property
    def joint_names(self) -> tuple[str, ...]:
        """NAO names of the five arm joints, e.g. ``("RShoulderPitch", ...)``."""
        return tuple(self.prefix + joint for joint in JOINTS)

    @property
    def hand_joint(self) -> str:
        """NAO name of the gripper actuator (open fraction 0..1)."""
        return self.prefix + "Hand"


def _any_case(value: object) -> object:
    """A side's name in lower case, without spaces (others unchanged).

    Raises:
        ValueError: for a name that is no side, saying which are.
    """
    if not isinstance(value, str):
        return value
    try:
        return Side.parse(value).value
    except UnknownArmError as error:
        raise ValueError(error.message) from None


#: ``Side`` in a file a person writes (a task, a marker map): ``"Left"``
#: and ``"RIGHT"`` read as the command line's ``--arm`` reads them.
SideAnyCase = Annotated[Side, BeforeValidator(_any_case)]
