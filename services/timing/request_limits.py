"""The motion limits a plan or timing request times with."""

from __future__ import annotations

from shared.messages import TimingLimits
from shared.robot.limits import JointLimits
from shared.robot.motion_limits import MotionLimits, asked_limits


def request_limits(joints: JointLimits, asked: TimingLimits | None) -> MotionLimits:
    """The arm's limits with the request's acceleration and jerk, if it gives any.

    Args:
        joints: Position and speed limits of the arm (``ArmModel.limits``).
        asked: The request's ``limits``; ``None``: the defaults.

    Raises:
        InvalidInputError: a limit above the bridge's safety net, naming the
            joint (``shared.robot.motion_limits.asked_limits``).
    """
    if asked is None:
        return asked_limits(joints)
    return asked_limits(joints, acceleration=asked.acceleration, jerk=asked.jerk)
