"""The wrist task of an IK step: its error and Jacobian columns for one posture."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from services.ik.kernel.chain import ChainState
from services.ik.kernel.small import Vec, cross, dot, norm, sub
from shared.geometry.palm import roll_error, roll_rate


def _vec(v: Sequence[float] | np.ndarray) -> Vec:
    return (float(v[0]), float(v[1]), float(v[2]))


class WristTask:
    """Put the wrist on ``position`` and, optionally, turn the palm to ``palm``.

    With ``radial`` False the task controls only the wrist's direction from
    the shoulder, not its distance: the error and Jacobian are projected on
    two directions normal to the shoulder-wrist line. That is the task of the
    primitives in which the shoulder swings an arm of fixed shape (S_R E_P
    W_P, S_R E_P W_PR): ElbowRoll is passive, so the distance is too.

    Build it with :meth:`make`, which accepts numpy arrays or sequences. A
    plain class, not a NamedTuple: compiled, it is built and read as a
    native object (the tracker makes one or two per path point).

    Attributes:
        position: Wanted wrist position in the torso frame [m].
        palm: Wanted palm direction (unit) or ``None``.
        sign: +1 for the right hand, -1 for the left (palm side).
        radial: Whether the distance from the shoulder is controlled.
        roll_left: Roll of the palm still to make at this point [rad]: the
            task asks for the palm turned to ``palm`` but for this much
            (0 at the goal), so that along a path the palm turns with the hand.
    """

    def __init__(
        self,
        position: Vec,
        palm: Vec | None,
        sign: float,
        radial: bool = True,
        roll_left: float = 0.0,
    ) -> None:
        self.position, self.palm, self.sign, self.radial = position, palm, sign, radial
        self.roll_left = roll_left

    @classmethod
    def make(
        cls,
        position: Sequence[float] | np.ndarray,
        palm: Sequence[float] | np.ndarray | None,
        sign: float,
        radial: bool = True,
    ) -> WristTask:
        """A task from any 3-sequences (numpy arrays included)."""
        return cls(_vec(position), None if palm is None else _vec(palm), sign, radial)

    def at(self, position: Sequence[float], roll_left: float = 0.0) -> WristTask:
        """The same task with another wrist position and roll still left [rad]."""
        return WristTask(_vec(position), self.palm, self.sign, self.radial, roll_left)

    def residual(self, st: ChainState) -> tuple[list[float], list[tuple[float, ...]]]:
        """(error, Jacobian columns) of the task at ``st``.

        Returns:
            error: Position error [m] (3 values, or 2 for the direction task),
                then the roll error [rad] if a palm direction is wanted
                (less ``roll_left``).
            cols: d(task)/dq_k for each joint k (5 tuples of as many values
                as ``error``); the roll entry is the roll's exact rate
                under the joint (``roll_rate``), not only the joint axis's
                part along the forearm: where a joint also swings the
                forearm relative to the wanted palm, the projection alone
                left the roll trailing its target along a path.
        """
        w, p = st.origins[4], self.position
        e = (p[0] - w[0], p[1] - w[1], p[2] - w[2])
        if self.radial:
            err = list(e)
            cols: list[tuple[float, ...]] = list(st.jw)
        else:
            t1, t2 = _tangents(sub(w, st.origins[0]))
            err = [dot(t1, e), dot(t2, e)]
            cols = [(dot(t1, c), dot(t2, c)) for c in st.jw]
        if self.palm is not None:
            rate = roll_rate(st.rot, self.sign, self.palm)
            err.append(roll_error(st.rot, self.sign, self.palm) - self.roll_left)
            cols = [(*c, dot(rate, a)) for c, a in zip(cols, st.axes, strict=True)]
        return err, cols

    def position_error(self, st: ChainState) -> float:
        """Distance from the wrist to ``position`` [m] (radial part included)."""
        return norm(sub(self.position, st.origins[4]))

    def palm_error(self, st: ChainState) -> float:
        """Absolute roll still needed to face the palm [rad] (0 without a palm)."""
        if self.palm is None:
            return 0.0
        return abs(roll_error(st.rot, self.sign, self.palm))


def _tangents(out: Vec) -> list[Vec]:
    """Two unit vectors normal to ``out`` and to each other."""
    length = norm(out)
    r = (out[0] / length, out[1] / length, out[2] / length)
    helper: Vec = (0.0, 0.0, 1.0) if abs(r[2]) < 0.9 else (1.0, 0.0, 0.0)
    t1 = cross(helper, r)
    n1 = norm(t1)
    t1 = (t1[0] / n1, t1[1] / n1, t1[2] / n1)
    return [t1, cross(r, t1)]


def controls_radius(active: tuple[int, ...]) -> bool:
    """False when the shoulder swings an arm of fixed shape (ElbowRoll passive).

    Such primitives (S_R E_P W_P, S_R E_P W_PR) move the wrist with the
    shoulder joints alone: they control its direction from the shoulder, not
    its distance.
    """
    joints = set(active)
    return not ({0, 1} <= joints and 3 not in joints)


__all__ = ["WristTask", "controls_radius"]
