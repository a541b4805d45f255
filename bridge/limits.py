"""The limits every command frame must respect: position, speed, acceleration, jerk."""

from __future__ import annotations

import numpy as np
import numpy.typing as npt

from shared.robot import Side, load_arm
from shared.robot.hand import hand_limits
from shared.robot.motion_limits import (
    JERK_TIME,
    NET_ACCELERATION_TIME,
    MotionLimits,
    motion_limits,
    net_limits,
)

#: Default acceleration limit as the time a joint takes to reach its speed
#: limit from rest [s]: limit = speed limit / this. A safety net for the
#: frames the bridge sends, above what the timing service's defaults produce
#: (NAO's arm motors reach their no-load speed in about a tenth of a second);
#: a request's own timing limits may not go above it.
RAMP_TIME = NET_ACCELERATION_TIME
#: Default jerk limit as the time a joint takes to build its acceleration
#: limit from zero [s]: limit = acceleration limit / this. The timing's own
#: ramp (``shared.robot.motion_limits.JERK_TIME``) on the bridge's looser
#: accelerations: 2.5 times the jerk the timing service's defaults allow.
JERK_RAMP_TIME = JERK_TIME


class FrameLimits(MotionLimits):
    """Limits of the joints a set of frames moves.

    ``MotionLimits`` with the bridge's looser defaults (:meth:`for_arm`).

    Attributes:
        names: NAO joint names, shape (n,).
        lower: Lower position limits [rad], shape (n,).
        upper: Upper position limits [rad], shape (n,).
        velocity: Speed limits [rad/s], shape (n,).
        acceleration: Acceleration limits [rad/s^2], shape (n,).
        jerk: Jerk limits [rad/s^3], shape (n,).
    """

    __slots__ = ()

    @classmethod
    def for_arm(
        cls,
        side: Side | str,
        acceleration: npt.ArrayLike | None = None,
        jerk: npt.ArrayLike | None = None,
    ) -> FrameLimits:
        """The limits of one arm's five joints, read from the robot description.

        Args:
            side: ``"right"`` or ``"left"``.
            acceleration: Acceleration limits [rad/s^2], scalar or shape (5,);
                default: speed limit / :data:`RAMP_TIME`.
            jerk: Jerk limits [rad/s^3], scalar or shape (5,); default:
                acceleration limit / :data:`JERK_RAMP_TIME`.

        Raises:
            InvalidInputError: a limit is not a positive finite number, or has
                the wrong shape.
        """
        joints = load_arm(side).limits
        if acceleration is None:
            acceleration = net_limits(joints).acceleration
        accel = motion_limits(joints, acceleration=acceleration).acceleration
        if jerk is None:
            jerk = accel / JERK_RAMP_TIME
        return cls(*motion_limits(joints, acceleration=accel, jerk=jerk))

    def with_hand(self, side: Side | str) -> FrameLimits:
        """These limits and, after them, the hand of ``side`` as one more joint.

        The hand's range (open fraction 0..1) and speed limit [1/s] are the
        robot description's; its acceleration and jerk limits the bridge's
        safety net, by the arm joints' rule (speed limit / :data:`RAMP_TIME`,
        that / :data:`JERK_RAMP_TIME`: 83.3 /s^2 and 1666 /s^3).
        """
        hand = net_limits(hand_limits(side))
        return FrameLimits(
            names=(*self.names, *hand.names),
            lower=_joined(self.lower, hand.lower),
            upper=_joined(self.upper, hand.upper),
            velocity=_joined(self.velocity, hand.velocity),
            acceleration=_joined(self.acceleration, hand.acceleration),
            jerk=_joined(self.jerk, hand.jerk),
        )


def _joined(mine: np.ndarray, theirs: np.ndarray) -> np.ndarray:
    """``mine`` then ``theirs``, as one read-only float array."""
    values = np.concatenate([mine, theirs]).astype(float)
    values.setflags(write=False)
    return values
