"""The grasping measure H_G (paper eq. 21)."""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import TYPE_CHECKING

from services.ik.kernel.chain import ChainState
from services.ik.measures.base import Measure
from services.ik.measures.elbow_travel import ElbowTravel
from services.ik.measures.ntpe import WristDiscomfortEnergy

if TYPE_CHECKING:
    import numpy as np


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
        target: Wrist target [m], 3 values.
        start_distance: d [m].
        k1: Weight of s [J/m].
        k2: Weight of NTPE [-].
    """

    def __init__(
        self,
        travel: ElbowTravel,
        ntpe: WristDiscomfortEnergy,
        target: Sequence[float] | np.ndarray,
        start_distance: float,
        k1: float,
        k2: float,
    ) -> None:
        self.travel = travel
        self.ntpe = ntpe
        self.target = (float(target[0]), float(target[1]), float(target[2]))
        self.d = max(float(start_distance), 1e-6)
        self.k1, self.k2 = k1, k2

    def blend(self, st: ChainState) -> float:
        """dd / d, clipped to [0, 1]: 1 at the start, 0 at the target."""
        w, t = st.origins[4], self.target
        dd = math.sqrt((t[0] - w[0]) ** 2 + (t[1] - w[1]) ** 2 + (t[2] - w[2]) ** 2)
        return min(max(dd / self.d, 0.0), 1.0)

    def value(self, st: ChainState) -> float:
        b = self.blend(st)
        return (
            self.k1 * self.travel.value(st) * (1.0 - b)
            + self.k2 * self.ntpe.value(st) * b
        )

    def gradient(self, st: ChainState) -> list[float]:
        b = self.blend(st)
        a, c = self.k1 * (1.0 - b), self.k2 * b
        travel, ntpe = self.travel.gradient(st), self.ntpe.gradient(st)
        return [a * travel[k] + c * ntpe[k] for k in range(len(travel))]
