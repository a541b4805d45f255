"""The palm a posture reached, measured against the direction asked.

The IK's orientation task is the palm's roll about the forearm
(``shared.geometry.palm.roll_error``): the paper's primitives orient NAO's
wrist by W_R, a roll, and NAO's wrist has that one joint. The forearm's
direction comes from the position task. So a posture the IK accepts has its
roll right, and its palm normal is off the wanted direction ``p`` by the
angle ``p`` makes with the plane across the forearm, ``asin(|p . a|)`` for
forearm axis ``a``. :func:`palm_reached` measures the angle itself, from the
IK's own forward kinematics, so that the answers can say it.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

from services.ik.kernel.chain import chain_for
from shared.geometry.palm import palm_normal
from shared.messages import PalmReached
from shared.robot.arm_model import ArmModel


def palm_angle(
    normal: Sequence[float] | np.ndarray, wanted: Sequence[float] | np.ndarray
) -> float:
    """Angle between a palm normal and a wanted direction [rad], 0 to pi.

    By ``atan2(|n x p|, n . p)``, exact near 0 and pi where ``acos`` is not.

    Args:
        normal: Palm normal, 3 values (any length but 0).
        wanted: Wanted palm direction, 3 values (any length but 0).
    """
    n, p = np.asarray(normal, dtype=float), np.asarray(wanted, dtype=float)
    return math.atan2(float(np.linalg.norm(np.cross(n, p))), float(n @ p))


def palm_reached(
    arm: ArmModel, q: Sequence[float] | np.ndarray, wanted: Sequence[float]
) -> PalmReached:
    """The palm normal of posture ``q`` and its angle from ``wanted``.

    Args:
        arm: The arm.
        q: Joint angles [rad], shape (5,).
        wanted: Wanted palm direction, torso frame, 3 values (unit after
            the message's validation).
    """
    rotation = chain_for(arm).state(q).wrist_rotation
    normal = palm_normal(rotation, arm.side.sign)
    return PalmReached(
        wanted=tuple(float(v) for v in wanted),
        normal=tuple(float(v) for v in normal),
        angle_deg=math.degrees(palm_angle(normal, wanted)),
    )
