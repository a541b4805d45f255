"""The palm direction and the hand's roll about the forearm.

NAO's wrist has one joint, WristYaw, turning the hand about the forearm axis
(the wrist frame's x axis). With five joints the wrist's orientation task is
therefore one-dimensional: the roll about the forearm that turns the palm
towards a wanted direction. At zero joint angles NAO's palms face each other,
so the palm normal is the wrist frame's +y axis on the right hand and -y on
the left.
"""

from __future__ import annotations

import math

import numpy as np

from shared.geometry.vectors import cross

#: Below this length of the wanted palm direction projected off the forearm
#: axis, roll cannot change how well the palm faces it (palm along forearm).
DEGENERATE = math.sin(math.radians(5.0))


def palm_normal(wrist_rotation: np.ndarray, sign: float) -> np.ndarray:
    """The palm's normal in the torso frame, unit, shape (3,).

    Args:
        wrist_rotation: Orientation of the wrist frame, shape (3, 3).
        sign: +1 for the right hand, -1 for the left.
    """
    return sign * wrist_rotation[:, 1]


def roll_error(wrist_rotation: np.ndarray, sign: float, palm: np.ndarray) -> float:
    """Roll about the forearm that best turns the palm towards ``palm`` [rad].

    Positive about the forearm axis (wrist frame x). Zero when ``palm`` lies
    within 5 degrees of the forearm axis, where roll does not matter.

    Args:
        wrist_rotation: Orientation of the wrist frame, shape (3, 3).
        sign: +1 for the right hand, -1 for the left.
        palm: Wanted palm direction, unit, shape (3,).
    """
    axis = wrist_rotation[:, 0]
    wanted = palm - float(palm @ axis) * axis
    norm = float(np.linalg.norm(wanted))
    if norm < DEGENERATE:
        return 0.0
    wanted = wanted / norm
    normal = palm_normal(wrist_rotation, sign)
    return math.atan2(float(axis @ cross(normal, wanted)), float(normal @ wanted))
