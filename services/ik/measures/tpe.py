"""Total potential energy, TPE (paper eq. 15-18)."""

from __future__ import annotations

import math

from services.ik.kernel.chain import ChainState
from services.ik.measures.base import Measure
from shared.geometry.swivel import swivel_and_gradient, swivel_angle


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

    def elastic(self, st: ChainState) -> float:
        """Spring energy mu (pi - phi)^2 / 2 [J] (eq. 17)."""
        phi = swivel_angle(st.origins[0], st.origins[2], st.origins[4])
        return 0.5 * self.mu * (math.pi - phi) ** 2

    def value(self, st: ChainState) -> float:
        return st.energy + self.elastic(st)

    def gradient(self, st: ChainState) -> list[float]:
        o = st.origins
        phi, dphi = swivel_and_gradient(o[0], o[2], o[4], st.je, st.jw)
        k = self.mu * (math.pi - phi)
        return [g - k * d for g, d in zip(st.grav, dphi, strict=True)]
