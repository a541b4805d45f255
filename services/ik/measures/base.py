"""The human performance measure interface: a value H and its gradient."""

from __future__ import annotations

from abc import ABC, abstractmethod

import numpy as np

from shared.robot.arm_model import Kinematics


class Measure(ABC):
    """A human performance measure H(q) to minimise in the null space (eq. 14).

    Subclasses give the value [J, or J-equivalent] and the gradient dH/dq
    [per rad], shape (5,), from one :class:`Kinematics` pass.
    """

    @abstractmethod
    def value(self, kin: Kinematics) -> float:
        """H at the posture ``kin.q``."""

    @abstractmethod
    def gradient(self, kin: Kinematics) -> np.ndarray:
        """dH/dq at ``kin.q``, shape (5,)."""


class NoMeasure(Measure):
    """H = 0: no null-space motion (the least-norm baseline)."""

    def value(self, kin: Kinematics) -> float:
        return 0.0

    def gradient(self, kin: Kinematics) -> np.ndarray:
        return np.zeros(kin.q.shape[0])
