"""TPE plus wrist discomfort, NTPE (paper eq. 19)."""

from __future__ import annotations

import numpy as np

from services.ik.measures.base import Measure
from services.ik.measures.tpe import TotalPotentialEnergy
from shared.robot.arm_model import Kinematics

WRIST = 4  # index of WristYaw in the joint vector


class WristDiscomfortEnergy(Measure):
    """f_NTPE = f_TPE + omega (theta_wa - theta_N,wa)^2 [J].

    Args:
        tpe: The total potential energy term.
        omega: Weight of the wrist discomfort [J/rad^2].
        centre: Centre angle of WristYaw theta_N,wa [rad].
    """

    def __init__(self, tpe: TotalPotentialEnergy, omega: float, centre: float) -> None:
        self.tpe = tpe
        self.omega = omega
        self.centre = centre

    def value(self, kin: Kinematics) -> float:
        return self.tpe.value(kin) + self.omega * (kin.q[WRIST] - self.centre) ** 2

    def gradient(self, kin: Kinematics) -> np.ndarray:
        grad = self.tpe.gradient(kin)
        grad[WRIST] += 2.0 * self.omega * (kin.q[WRIST] - self.centre)
        return grad
