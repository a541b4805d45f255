"""A spring pulling the elbow swivel angle to a goal (function primitive)."""

from __future__ import annotations

import math

from services.ik.kernel.chain import ChainState
from services.ik.measures.base import Measure
from shared.geometry.swivel import swivel_and_gradient, swivel_angle


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

    def error(self, st: ChainState) -> float:
        """phi - phi_goal, wrapped [rad]."""
        phi = swivel_angle(st.origins[0], st.origins[2], st.origins[4])
        return wrap(phi - self.goal)

    def value(self, st: ChainState) -> float:
        return 0.5 * self.weight * self.error(st) ** 2

    def gradient(self, st: ChainState) -> list[float]:
        o = st.origins
        phi, dphi = swivel_and_gradient(o[0], o[2], o[4], st.je, st.jw)
        k = self.weight * wrap(phi - self.goal)
        return [k * d for d in dphi]
