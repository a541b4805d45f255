"""TPE plus wrist discomfort, NTPE (paper eq. 19)."""

from __future__ import annotations

from typing import Final

from services.ik.kernel.chain import ChainState
from services.ik.measures.base import Measure
from services.ik.measures.tpe import TotalPotentialEnergy

WRIST: Final = 4  # index of WristYaw in the joint vector


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

    def value(self, st: ChainState) -> float:
        return self.tpe.value(st) + self.omega * (st.qf[WRIST] - self.centre) ** 2

    def gradient(self, st: ChainState) -> list[float]:
        grad = self.tpe.gradient(st)
        grad[WRIST] += 2.0 * self.omega * (st.qf[WRIST] - self.centre)
        return grad
