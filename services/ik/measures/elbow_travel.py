"""Minimum elbow travel (paper eq. 20)."""

from __future__ import annotations

import math

import numpy as np

from services.ik.measures.base import Measure
from shared.robot.arm_model import Kinematics

#: Smoothing length that keeps s differentiable at zero travel [m].
SMOOTH = 1e-4


class ElbowTravel(Measure):
    """s = |elbow - elbow_0| [m], smoothed as sqrt(|.|^2 + eps^2) - eps.

    Args:
        start: Elbow position when the grasping movement begins [m], shape (3,).
    """

    def __init__(self, start: np.ndarray) -> None:
        self.start = np.asarray(start, dtype=float).copy()

    def value(self, kin: Kinematics) -> float:
        d = kin.elbow - self.start
        return math.sqrt(float(d @ d) + SMOOTH**2) - SMOOTH

    def gradient(self, kin: Kinematics) -> np.ndarray:
        d = kin.elbow - self.start
        return (d / math.sqrt(float(d @ d) + SMOOTH**2)) @ kin.elbow_jacobian
