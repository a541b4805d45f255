"""A palm the IK could not turn while reaching: reach first, then turn the wrist.

The IK solves the wrist's position and the palm's roll about the forearm as
one task. When the roll that faces the palm lies beyond WristYaw's range,
WristYaw stops on its bound and the other joints take the roll up, pulling
the wrist off the target: the solver stopped 3.5 to 130 mm from targets
the arm reaches (13 of 150 random reachable targets with random palms), and
the answer said the target was out of reach.

WristYaw turns the hand about the forearm's axis, on which the wrist lies,
so it never moves the wrist. Given a posture that reaches the target
without the palm, :func:`turn_wrist` turns WristYaw by the roll that faces
the palm: within the range, that posture does both; beyond it, the palm
cannot be faced there and the error says so, with the WristYaw it needs.
"""

from __future__ import annotations

import math

import numpy as np

from services.ik.palm_reached import palm_reached
from shared.errors import PalmRollOutOfRangeError
from shared.geometry.palm import roll_error
from shared.robot.arm_model import ArmModel

WRIST_YAW = 4


def turn_wrist(
    arm: ArmModel, q: np.ndarray, target: np.ndarray, palm: np.ndarray
) -> np.ndarray:
    """``q`` [rad], (5,), with WristYaw turned to face the palm to ``palm``.

    Args:
        arm: The arm.
        q: A posture whose wrist is at ``target`` [rad], shape (5,).
        target: The wrist target [m], shape (3,), for the error.
        palm: The wanted palm direction, unit, shape (3,).

    Raises:
        PalmRollOutOfRangeError: no WristYaw within its range faces it.
    """
    low, high = arm.limits.lower[WRIST_YAW], arm.limits.upper[WRIST_YAW]
    needed = q[WRIST_YAW] + roll_error(arm.rotation(q, "wrist"), arm.side.sign, palm)
    turns = [needed + 2.0 * math.pi * k for k in (-1, 0, 1)]
    within = [v for v in turns if low <= v <= high]
    if within:
        turned = np.array(q, dtype=float)
        turned[WRIST_YAW] = min(within, key=lambda v: abs(v - q[WRIST_YAW]))
        return turned
    nearest = min(turns, key=lambda v: _beyond(v, low, high))
    raise _out_of_range(arm, q, target, palm, nearest)


def _beyond(value: float, low: float, high: float) -> float:
    """How far ``value`` lies outside ``low..high`` (0 within)."""
    return max(low - value, value - high, 0.0)


def _out_of_range(
    arm: ArmModel, q: np.ndarray, target: np.ndarray, palm: np.ndarray, needed: float
) -> PalmRollOutOfRangeError:
    """The error for WristYaw needing ``needed`` [rad] at posture ``q``."""
    low, high = arm.limits.lower[WRIST_YAW], arm.limits.upper[WRIST_YAW]
    nearest = np.array(q, dtype=float)
    nearest[WRIST_YAW] = min(max(needed, low), high)
    shoulder = arm.fk(q).shoulder
    wrist = arm.fk(q).wrist
    reached = palm_reached(arm, nearest, tuple(float(v) for v in palm))
    return PalmRollOutOfRangeError(
        target,
        arm=arm.side.value,
        distance=float(np.linalg.norm(np.asarray(target) - shoulder)),
        reach=arm.reach,
        residual=float(np.linalg.norm(wrist - np.asarray(target))),
        palm=palm,
        wrist_yaw=needed,
        wrist_yaw_range=(float(low), float(high)),
        posture=q,
        nearest_angle=math.radians(reached.angle_deg),
    )
