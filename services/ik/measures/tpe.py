"""Total potential energy, TPE (paper eq. 15-18)."""

from __future__ import annotations

import math

from services.ik.kernel.chain import ChainState
from services.ik.measures.base import Measure
from shared.geometry.swivel import elbow_offset_and_gradient, swivel_and_gradient


class TotalPotentialEnergy(Measure):
    """H_R = m_u g h_u + m_l g h_l + mu (pi - phi)^2 / 2 [J].

    The gravitational part (eq. 16) is the potential energy of the arm's links
    (upper arm: shoulder and biceps links; lower arm: elbow, forearm and hand)
    from the robot description; its gradient is the gravity torque vector.

    The elastic part (eq. 17) is the paper's "virtual torsion spring with
    variable stiffness" on the elbow swivel angle phi (see
    :mod:`shared.geometry.swivel`), relaxed with the elbow down. The
    stiffness varies with how well phi is defined: mu = mu0 (r / L_u)^2, r the
    elbow's distance from the shoulder-wrist line and L_u the upper arm's
    length. A straight arm has no swivel (r = 0) and no spring; without this,
    the spring would spin a hanging, nearly straight arm about its own axis
    at the start of every reach, chasing an angle that means nothing there.

    Args:
        mu: mu0 [J/rad^2]: the stiffness when the elbow is as far from the
            shoulder-wrist line as the upper arm is long.
    """

    def __init__(self, mu: float) -> None:
        self.mu = mu

    def _spring(self, st: ChainState) -> tuple[float, float]:
        """(stiffness [J/rad^2], pi - phi [rad]) at ``st``."""
        o = st.origins
        r2, _ = elbow_offset_and_gradient(o[0], o[2], o[4], [], [])
        phi = swivel_and_gradient(o[0], o[2], o[4], [], [])[0]
        return self.mu * r2 / _upper_arm_squared(st), math.pi - phi

    def elastic(self, st: ChainState) -> float:
        """Spring energy mu (pi - phi)^2 / 2 [J] (eq. 17), mu as above."""
        stiffness, bend = self._spring(st)
        return 0.5 * stiffness * bend * bend

    def value(self, st: ChainState) -> float:
        return st.energy + self.elastic(st)

    def gradient(self, st: ChainState) -> list[float]:
        o = st.origins
        phi, dphi = swivel_and_gradient(o[0], o[2], o[4], st.je, st.jw)
        r2, dr2 = elbow_offset_and_gradient(o[0], o[2], o[4], st.je, st.jw)
        bend = math.pi - phi
        k = self.mu / _upper_arm_squared(st)
        # d/dq [k r2 bend^2 / 2] = k (bend^2 / 2) dr2 - k r2 bend dphi
        a, b = 0.5 * k * bend * bend, k * r2 * bend
        grav = st.grav
        return [grav[k] + a * dr2[k] - b * dphi[k] for k in range(len(grav))]


def _upper_arm_squared(st: ChainState) -> float:
    """L_u^2 [m^2]: the squared shoulder-to-elbow distance (constant for an arm)."""
    s, e = st.origins[0], st.origins[2]
    return (e[0] - s[0]) ** 2 + (e[1] - s[1]) ** 2 + (e[2] - s[2]) ** 2
