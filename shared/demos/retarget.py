"""Human arm data to NAO: keep the directions of upper arm and forearm.

The retargeted shoulder is NAO's; the elbow lies NAO's upper-arm length from
it along the human upper arm's direction, and the wrist NAO's forearm length
from the elbow along the human forearm's direction (SPEC, "Demonstrations
and fitting"). Angles between the segments, the swivel of the arm plane and
the wrist's orientation are kept; only the lengths change.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from shared.demos.rotations import FloatArray, unit
from shared.robot.arm_model import load_arm
from shared.robot.postures import rest
from shared.robot.side import Side


class ArmSize(NamedTuple):
    """Where an arm's shoulder is and how long its segments are.

    Attributes:
        shoulder: Shoulder position [m], shape (3,).
        upper_arm: Shoulder-to-elbow length L_u [m].
        forearm: Elbow-to-wrist length L_f [m].
    """

    shoulder: FloatArray
    upper_arm: float
    forearm: float


def nao_arm_size(side: Side | str) -> ArmSize:
    """NAO's shoulder (torso frame) and segment lengths, from the robot description."""
    arm = load_arm(side)
    shoulder = arm.fk(rest(arm.side)).shoulder
    return ArmSize(shoulder, arm.upper_arm_length, arm.forearm_length)


class ArmTrack(NamedTuple):
    """Shoulder, elbow and wrist positions over time [m], each shape (n, 3)."""

    shoulder: FloatArray
    elbow: FloatArray
    wrist: FloatArray


def retarget(track: ArmTrack, size: ArmSize) -> ArmTrack:
    """The same movement made by an arm of ``size`` (directions kept).

    Args:
        track: Human shoulder, elbow and wrist positions [m], each (n, 3).
        size: The target arm's shoulder and segment lengths.

    Returns:
        The retargeted positions [m], each shape (n, 3).
    """
    upper = unit(track.elbow - track.shoulder)
    fore = unit(track.wrist - track.elbow)
    shoulder = np.broadcast_to(size.shoulder, track.shoulder.shape).copy()
    elbow = shoulder + size.upper_arm * upper
    wrist = elbow + size.forearm * fore
    return ArmTrack(shoulder, elbow, wrist)
