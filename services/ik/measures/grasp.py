"""The grasping measure H_G (paper eq. 21)."""

from __future__ import annotations

import numpy as np

from services.ik.measures.base import Measure
from services.ik.measures.elbow_travel import ElbowTravel
from services.ik.measures.ntpe import WristDiscomfortEnergy
from shared.robot.arm_model import Kinematics


class GraspBlend(Measure):
    """H_G = k1 s (d - dd)/d + k2 f_NTPE dd/d.

    d is the wrist-to-target distance when the grasping movement begins
    (constant), dd the current one. At the start H_G is NTPE; at the target
    it is the elbow travel: the blend hands over smoothly from reaching to
    grasping. dd is a schedule here, not differentiated: the null-space
    projection of eq. 14 removes any gradient along the wrist task anyway.

    Args:
        travel: Elbow-travel term s.
        ntpe: NTPE term.
        target: Wrist target [m], shape (3,).
        start_distance: d [m].
        k1: Weight of s [J/m].
        k2: Weight of NTPE [-].
    """

    def __init__(
        self,
        travel: ElbowTravel,
        ntpe: WristDiscomfortEnergy,
        target: np.ndarray,
        start_distance: float,
        k1: float,
        k2: float,
    ) -> None:
        self.travel = travel
        self.ntpe = ntpe
        self.target = np.asarray(target, dtype=float).copy()
        self.d = max(float(start_distance), 1e-6)
        self.k1, self.k2 = k1, k2

    def blend(self, kin: Kinematics) -> float:
        """Dd / d, clipped to [0, 1]: 1 at the start, 0 at the target."""
        dd = float(np.linalg.norm(self.target - kin.wrist))
        return min(max(dd / self.d, 0.0), 1.0)

    def value(self, kin: Kinematics) -> float:
        b = self.blend(kin)
        return (
            self.k1 * self.travel.value(kin) * (1.0 - b)
            + self.k2 * self.ntpe.value(kin) * b
        )

    def gradient(self, kin: Kinematics) -> np.ndarray:
        b = self.blend(kin)
        return self.k1 * (1.0 - b) * self.travel.gradient(
            kin
        ) + self.k2 * b * self.ntpe.gradient(kin)
