"""Total potential energy, TPE (paper eq. 15-18)."""

from __future__ import annotations

import math

import numpy as np

from services.ik.measures.base import Measure
from shared.geometry.swivel import swivel_angle, swivel_gradient
from shared.robot.arm_model import Kinematics


class TotalPotentialEnergy(Measure):
    """H_R = m_u g h_u + m_l g h_l + mu (pi - phi)^2 / 2 [J].

    The gravitational part (eq. 16) is the potential energy of the arm's links
    (upper arm: shoulder and biceps links; lower arm: elbow, forearm and hand)
    from the robot description; its gradient is the gravity torque vector.
    The elastic part (eq. 17) is a torsion spring on the elbow swivel angle
    phi (see :mod:`shared.geometry.swivel`), relaxed with the elbow down.

    Args:
        mu: Spring stiffness [J/rad^2].
    """

    def __init__(self, mu: float) -> None:
        self.mu = mu

    def elastic(self, kin: Kinematics) -> float:
        """Spring energy mu (pi - phi)^2 / 2 [J] (eq. 17)."""
        phi = swivel_angle(kin.shoulder, kin.elbow, kin.wrist)
        return 0.5 * self.mu * (math.pi - phi) ** 2

    def value(self, kin: Kinematics) -> float:
        return kin.gravity_energy + self.elastic(kin)

    def gradient(self, kin: Kinematics) -> np.ndarray:
        phi = swivel_angle(kin.shoulder, kin.elbow, kin.wrist)
        dphi = swivel_gradient(
            kin.shoulder, kin.elbow, kin.wrist, kin.elbow_jacobian, kin.wrist_jacobian
        )
        return kin.gravity_gradient - self.mu * (math.pi - phi) * dphi
