"""The NAO arm: robot description, kinematics, limits and reference postures."""

from shared.robot.arm_model import ArmModel, ArmPoints, Kinematics, load_arm
from shared.robot.limits import JointLimits
from shared.robot.motion_limits import MotionLimits, motion_limits
from shared.robot.side import JOINTS, Side

__all__ = [
    "JOINTS",
    "ArmModel",
    "ArmPoints",
    "JointLimits",
    "Kinematics",
    "MotionLimits",
    "Side",
    "load_arm",
    "motion_limits",
]
