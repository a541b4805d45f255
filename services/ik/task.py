"""The wrist task of an IK step: its error and Jacobian columns for one posture."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from services.ik.kernel.chain import ChainState
from services.ik.kernel.small import Vec, dot, norm, sub
from shared.geometry.palm import roll_error, roll_rate


def _vec(v: Sequence[float] | np.ndarray) -> Vec:
    return (float(v[0]), float(v[1]), float(v[2]))


class WristTask:
    """Put the wrist on ``position`` and, optionally, turn the palm to ``palm``.

    Build it with :meth:`make`, which accepts numpy arrays or sequences. A
    plain class, not a NamedTuple: compiled, it is built and read as a
    native object (the tracker makes one or two per path point).

    Attributes:
        position: Wanted wrist position in the torso frame [m].
        palm: Wanted palm direction (unit) or ``None``.
        sign: +1 for the right hand, -1 for the left (palm side).
        roll_left: Roll of the palm still to make at this point [rad]: the
            task asks for the palm turned to ``palm`` but for this much
            (0 at the goal), so that along a path the palm turns with the hand.
    """

    def __init__(
        self,
        position: Vec,
        palm: Vec | None,
        sign: float,
        roll_left: float = 0.0,
    ) -> None:
        self.position, self.palm, self.sign = position, palm, sign
        self.roll_left = roll_left

    @classmethod
    def make(
        cls,
        position: Sequence[float] | np.ndarray,
        palm: Sequence[float] | np.ndarray | None,
        sign: float,
    ) -> WristTask:
        """A task from any 3-sequences (numpy arrays included)."""
        return cls(_vec(position), None if palm is None else _vec(palm), sign)

    def at(self, position: Sequence[float], roll_left: float = 0.0) -> WristTask:
        """The same task with another wrist position and roll still left [rad]."""
        return WristTask(_vec(position), self.palm, self.sign, roll_left)

    def residual(self, st: ChainState) -> tuple[list[float], list[tuple[float, ...]]]:
        """(error, Jacobian columns) of the task at ``st``.

        Returns:
            error: Position error [m] (3 values), then the roll error [rad]
                if a palm direction is wanted (less ``roll_left``).
            cols: d(task)/dq_k for each joint k (5 tuples of as many values
                as ``error``); the roll entry is the roll's exact rate
                under the joint (``roll_rate``), not only the joint axis's
                part along the forearm: where a joint also swings the
                forearm relative to the wanted palm, the projection alone
                left the roll trailing its target along a path.
        """
        w, p = st.origins[4], self.position
        e = (p[0] - w[0], p[1] - w[1], p[2] - w[2])
        err = list(e)
        cols: list[tuple[float, ...]] = list(st.jw)
        if self.palm is not None:
            rate = roll_rate(st.rot, self.sign, self.palm)
            err.append(roll_error(st.rot, self.sign, self.palm) - self.roll_left)
            cols = [(*c, dot(rate, a)) for c, a in zip(cols, st.axes, strict=True)]
        return err, cols

    def position_error(self, st: ChainState) -> float:
        """Distance from the wrist to ``position`` [m]."""
        return norm(sub(self.position, st.origins[4]))

    def palm_error(self, st: ChainState) -> float:
        """Absolute roll still needed to face the palm [rad] (0 without a palm)."""
        if self.palm is None:
            return 0.0
        return abs(roll_error(st.rot, self.sign, self.palm))


__all__ = ["WristTask"]
