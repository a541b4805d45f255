"""Acceleration and jerk limits a request times with, instead of the defaults."""

from __future__ import annotations

from typing import Annotated

from pydantic import AfterValidator

from shared.messages.base import Message

#: Joints of an arm, so values per joint.
JOINTS = 5


def _per_joint(value: float | tuple[float, ...]) -> float | tuple[float, ...]:
    """``value`` if it is one positive limit, or five."""
    values = value if isinstance(value, tuple) else (value,)
    if len(values) not in (1, JOINTS):
        raise ValueError(
            f"give one limit for every joint or {JOINTS} (ShoulderPitch to "
            f"WristYaw), not {len(values)}"
        )
    if not all(v > 0.0 for v in values):
        raise ValueError("a limit must be a positive number")
    return value


#: One limit for every joint, or one per joint (ShoulderPitch .. WristYaw).
PerJoint = Annotated[float | tuple[float, ...], AfterValidator(_per_joint)]


class TimingLimits(Message):
    """The timing's acceleration and jerk limits, where the defaults will not do.

    The speed limits and joint ranges are always the robot description's.
    A limit may be lower than the default (a gentler movement) or higher, up
    to the bridge's safety net (``shared.robot.motion_limits.net_limits``);
    above it the request is refused, since the bridge would refuse the
    trajectory.

    Attributes:
        acceleration: [rad/s^2], one value or five; ``None``: the default,
            speed limit / 0.25 s.
        jerk: [rad/s^3], one value or five; ``None``: the default, the
            acceleration limit (the given one, if given) / 0.05 s.
    """

    acceleration: PerJoint | None = None
    jerk: PerJoint | None = None
