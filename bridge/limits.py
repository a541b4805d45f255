"""The limits every command frame must respect: position, speed, acceleration, jerk."""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
import numpy.typing as npt

from shared.robot import Side, load_arm
from shared.robot.motion_limits import JERK_TIME

#: Default acceleration limit as the time a joint takes to reach its speed
#: limit from rest [s]: limit = speed limit / this. A safety net for the
#: frames the bridge sends, above what the timing service's defaults produce
#: (NAO's arm motors reach their no-load speed in about a tenth of a second).
RAMP_TIME = 0.1
#: Default jerk limit as the time a joint takes to build its acceleration
#: limit from zero [s]: limit = acceleration limit / this. The timing's own
#: ramp (``shared.robot.motion_limits.JERK_TIME``) on the bridge's looser
#: accelerations: 2.5 times the jerk the timing service's defaults allow.
JERK_RAMP_TIME = JERK_TIME


class FrameLimits(NamedTuple):
    """Limits of the joints a set of frames moves.

    Attributes:
        names: NAO joint names, shape (n,).
        lower: Lower position limits [rad], shape (n,).
        upper: Upper position limits [rad], shape (n,).
        velocity: Speed limits [rad/s], shape (n,).
        acceleration: Acceleration limits [rad/s^2], shape (n,).
        jerk: Jerk limits [rad/s^3], shape (n,).
    """

    names: tuple[str, ...]
    lower: np.ndarray
    upper: np.ndarray
    velocity: np.ndarray
    acceleration: np.ndarray
    jerk: np.ndarray

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
        """
        limits = load_arm(side).limits
        if acceleration is None:
            accel = limits.velocity / RAMP_TIME
        else:
            accel = np.broadcast_to(np.asarray(acceleration, dtype=float), (5,))
        if jerk is None:
            jerks = accel / JERK_RAMP_TIME
        else:
            jerks = np.broadcast_to(np.asarray(jerk, dtype=float), (5,))
        return cls(
            names=limits.names,
            lower=limits.lower.copy(),
            upper=limits.upper.copy(),
            velocity=limits.velocity.copy(),
            acceleration=np.array(accel, dtype=float),
            jerk=np.array(jerks, dtype=float),
        )
