"""NAO's hand (gripper) as one more actuator: its range and motion limits.

The hand's value is its open fraction, 0 closed to 1 open (NAOqi's
``RHand``/``LHand``), and its speed limit is in the robot description
(``nao_arms.urdf``: 8.33 per second), read from there as the arm joints'
are. Acceleration and jerk limits follow the arm joints' rule
(``shared.robot.motion_limits``): by default full speed from rest in
``ACCELERATION_TIME`` and full acceleration built in ``JERK_TIME``
(33.3 /s^2, 666 /s^3), so a minimum-jerk close from fully open takes 0.45 s
(``services.timing.hand``), near the half second NAO's hand takes; the
robot bridge's safety net is the arm's too (``net_limits``).
"""

from __future__ import annotations

from functools import cache

import numpy as np
import pinocchio as pin

from shared.robot.arm_model import urdf_text
from shared.robot.limits import JointLimits
from shared.robot.motion_limits import MotionLimits, motion_limits
from shared.robot.side import Side


@cache
def _hand_limits(side: Side) -> JointLimits:
    model = pin.buildModelFromXML(urdf_text())
    joint = model.joints[model.getJointId(side.hand_joint)]

    def one(values: np.ndarray, index: int) -> np.ndarray:
        array = np.array([float(values[index])])
        array.setflags(write=False)
        return array

    return JointLimits(
        names=(side.hand_joint,),
        lower=one(model.lowerPositionLimit, joint.idx_q),
        upper=one(model.upperPositionLimit, joint.idx_q),
        velocity=one(model.velocityLimit, joint.idx_v),
        effort=one(model.effortLimit, joint.idx_v),
    )


def hand_limits(side: Side | str) -> JointLimits:
    """The hand's range [-] (open fraction), speed limit [1/s] and torque [N m].

    A one-joint ``JointLimits`` (shape (1,) each), read from the robot
    description.
    """
    return _hand_limits(Side.parse(side))


def hand_motion_limits(side: Side | str) -> MotionLimits:
    """The hand's default limits for planning [-, 1/s, 1/s^2, 1/s^3], shape (1,)."""
    return motion_limits(hand_limits(side))


__all__ = ["hand_limits", "hand_motion_limits"]
