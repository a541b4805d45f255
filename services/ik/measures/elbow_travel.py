"""Minimum elbow travel (paper eq. 20)."""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Final

from services.ik.kernel.chain import ChainState
from services.ik.measures.base import Measure

#: Smoothing length that keeps s differentiable at zero travel [m].
SMOOTH: Final = 1e-4


class ElbowTravel(Measure):
    """s = |elbow - elbow_0| [m], smoothed as sqrt(|.|^2 + eps^2) - eps.

    Args:
        start: Elbow position when the grasping movement begins [m], 3 values.
    """

    def __init__(self, start: Sequence[float]) -> None:
        self.start = (float(start[0]), float(start[1]), float(start[2]))

    def _offset(self, st: ChainState) -> tuple[float, float, float, float]:
        e, s = st.origins[2], self.start
        dx, dy, dz = e[0] - s[0], e[1] - s[1], e[2] - s[2]
        return dx, dy, dz, math.sqrt(dx * dx + dy * dy + dz * dz + SMOOTH**2)

    def value(self, st: ChainState) -> float:
        return self._offset(st)[3] - SMOOTH

    def gradient(self, st: ChainState) -> list[float]:
        dx, dy, dz, length = self._offset(st)
        return [(dx * c[0] + dy * c[1] + dz * c[2]) / length for c in st.je]
