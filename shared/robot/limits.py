"""Joint limits of one arm, read from the robot description."""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from shared.errors import JointLimitError
from shared.robot.postures import MIRROR

#: Slack when checking a posture against its range [rad]: float round-off only.
POSITION_SLACK = 1e-9


class JointLimits(NamedTuple):
    """Position, speed and torque limits of a set of joints.

    Attributes:
        names: NAO joint names, shape (n,).
        lower: Lower position limits [rad], shape (n,).
        upper: Upper position limits [rad], shape (n,).
        velocity: Speed limits [rad/s], shape (n,).
        effort: Torque limits [N m], shape (n,).
    """

    names: tuple[str, ...]
    lower: np.ndarray
    upper: np.ndarray
    velocity: np.ndarray
    effort: np.ndarray

    @property
    def middle(self) -> np.ndarray:
        """Centre of each range [rad], shape (n,)."""
        return 0.5 * (self.lower + self.upper)

    @property
    def span(self) -> np.ndarray:
        """Width of each range [rad], shape (n,)."""
        return self.upper - self.lower

    def contains(self, q: np.ndarray, slack: float = POSITION_SLACK) -> bool:
        """True if every angle of ``q`` (shape (..., n)) lies in its range [rad]."""
        q = np.asarray(q, dtype=float)
        return bool(np.all(q >= self.lower - slack) and np.all(q <= self.upper + slack))

    def check(self, q: np.ndarray, where: str = "") -> None:
        """Raise ``JointLimitError`` naming the first joint of ``q`` out of range.

        Args:
            q: Joint angles [rad], shape (n,).
            where: Context for the message, e.g. ``"at sample 12"``.
        """
        q = np.asarray(q, dtype=float)
        for name, value, low, high in zip(
            self.names, q, self.lower, self.upper, strict=False
        ):
            if not low - POSITION_SLACK <= value <= high + POSITION_SLACK:
                hint = self._hint(q) or self._other_arm_hint(q)
                raise JointLimitError(name, value, low, high, where, hint)

    def _hint(self, q: np.ndarray) -> str:
        """``"; it looks like degrees ..."`` if ``q`` (shape (n,)) would fit so.

        Said only if two angles or more are beyond a turn (no NAO joint's
        range is) and every angle read as degrees lies in its range:
        ``--start 90 -10 45 30 0`` was refused as "90 rad" with no word of
        the likely slip. One such angle is a typo more likely than degrees
        (``1.5 -0.2 0.5 8 0``: read as degrees, every angle but the elbow
        roll's would be near 0).
        """
        if len(q) != len(self.names) or np.sum(np.abs(q) > 2.0 * np.pi) < 2:
            return ""
        radians = np.deg2rad(q)
        if not self.contains(radians):
            return ""
        said = ", ".join(f"{x:.4f}" for x in radians)
        return (
            f"; it looks like degrees: angles are in radians, and ({said}) rad "
            "is within every joint's range"
        )

    def _other_arm_hint(self, q: np.ndarray) -> str:
        """``"; if it is a posture of the right arm, ..."`` if it may be one.

        A right-arm posture typed for the left arm (or the reverse) was
        refused naming one joint out of range, with no word of the signs:
        the mirror image keeps ShoulderPitch and negates the other four
        (``shared.robot.postures.mirror``). Said only if ``q``, shape (5,),
        mirrored lies within every range of this arm; as a possibility, since
        one sign mistyped (ElbowRoll's, say) can look the same.
        """
        if len(q) != len(MIRROR) or len(self.names) != len(MIRROR):
            return ""
        mirrored = q * MIRROR
        if not self.contains(mirrored):
            return ""
        this = "left" if self.names[0].startswith("L") else "right"
        other = "right" if this == "left" else "left"
        said = ", ".join(f"{x + 0.0:.4f}" for x in mirrored)  # + 0.0: no -0.0000
        return (
            f"; if it is a posture of the {other} arm, the {this} arm's mirror "
            f"of it (ShoulderPitch kept, the other joints negated) is ({said}) rad"
        )

    def clip(self, q: np.ndarray) -> np.ndarray:
        """``q`` clipped into the ranges [rad], shape (..., n)."""
        return np.clip(q, self.lower, self.upper)
