"""A spring pulling the elbow swivel angle to a goal (function primitive)."""

from __future__ import annotations

import math

import numpy as np

from services.ik.measures.base import Measure
from shared.geometry.swivel import swivel_angle, swivel_gradient
from shared.robot.arm_model import Kinematics


def wrap(angle: float) -> float:
    """``angle`` wrapped into [-pi, pi) [rad]."""
    return (angle + math.pi) % (2.0 * math.pi) - math.pi


class SwivelGoal(Measure):
    """H = w * wrap(phi - phi_goal)^2 / 2 [J]: swivel the elbow round the held wrist.

    Used by S_R E_P W_R, whose null-space motion moves the elbow (to avoid an
    obstacle) while the wrist stays put.

    Args:
        goal: Wanted swivel angle phi [rad] (pi: elbow straight down).
        weight: Stiffness w [J/rad^2].
    """

    def __init__(self, goal: float, weight: float) -> None:
        self.goal = goal
        self.weight = weight

    def error(self, kin: Kinematics) -> float:
        """Phi - phi_goal, wrapped [rad]."""
        return wrap(swivel_angle(kin.shoulder, kin.elbow, kin.wrist) - self.goal)

    def value(self, kin: Kinematics) -> float:
        return 0.5 * self.weight * self.error(kin) ** 2

    def gradient(self, kin: Kinematics) -> np.ndarray:
        dphi = swivel_gradient(
            kin.shoulder, kin.elbow, kin.wrist, kin.elbow_jacobian, kin.wrist_jacobian
        )
        return self.weight * self.error(kin) * dphi
