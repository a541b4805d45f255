"""The human performance measure interface: a value H and its gradient."""

from __future__ import annotations

from abc import ABC, abstractmethod

from services.ik.kernel.chain import ChainState


class Measure(ABC):
    """A human performance measure H(q) to minimise in the null space (eq. 14).

    Subclasses give the value [J, or J-equivalent] and the gradient dH/dq
    [per rad], five floats, from one :class:`ChainState`.
    """

    @abstractmethod
    def value(self, st: ChainState) -> float:
        """H at the posture ``st.qf``."""

    @abstractmethod
    def gradient(self, st: ChainState) -> list[float]:
        """dH/dq at ``st.qf``, five floats."""


class NoMeasure(Measure):
    """H = 0: no null-space motion (the least-norm baseline)."""

    def value(self, st: ChainState) -> float:
        return 0.0

    def gradient(self, st: ChainState) -> list[float]:
        return [0.0] * 5
