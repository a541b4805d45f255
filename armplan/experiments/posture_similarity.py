"""Posture similarity S of the paper's equations 22-23.

For a robot posture theta_r and a human posture theta_h (both NAO joint
angles [rad], N = 5 joints):

    dist = ( sum_i ((theta_ri - theta_hi) / (theta_ri,max - theta_ri,min))^2 )^(1/2)
    S    = 1 / (1 + dist)                                     (eq. 22-23)

with each joint's range from the robot file (``shared.robot``). S is 1 for
identical postures and falls to 1 / (1 + sqrt(N)) when every joint is at
opposite ends of its range.
"""

from __future__ import annotations

import numpy as np

from shared.errors import InvalidInputError
from shared.robot.limits import JointLimits


def posture_distance(
    robot: np.ndarray, human: np.ndarray, limits: JointLimits
) -> np.ndarray:
    """dist of eq. 23 [-], shape (...): range-normalised Euclidean distance.

    Args:
        robot: Robot postures [rad], shape (..., N).
        human: Human postures [rad], shape (..., N).
        limits: The joints' ranges, N of them.

    Raises:
        InvalidInputError: if the shapes do not match the N joints.
    """
    robot, human = np.asarray(robot, float), np.asarray(human, float)
    span = np.asarray(limits.upper, float) - np.asarray(limits.lower, float)
    if robot.shape != human.shape or robot.shape[-1:] != span.shape:
        raise InvalidInputError(
            f"postures of shapes {robot.shape} and {human.shape} do not match "
            f"{span.shape[0]} joints",
            field="postures",
        )
    return np.sqrt(np.sum(((robot - human) / span) ** 2, axis=-1))


def posture_similarity(
    robot: np.ndarray, human: np.ndarray, limits: JointLimits
) -> np.ndarray:
    """S of eq. 22 in (0, 1], shape (...) (see ``posture_distance``)."""
    return 1.0 / (1.0 + posture_distance(robot, human, limits))


def least_similarity(joints: int) -> float:
    """The smallest S over postures within the ranges: 1 / (1 + sqrt(N))."""
    return 1.0 / (1.0 + float(np.sqrt(joints)))
