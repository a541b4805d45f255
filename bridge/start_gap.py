"""Whether the arm must first move to a trajectory's start.

The frames are checked from the trajectory's own start before the robot is
contacted. The arm, though, is wherever it was last commanded: within
``START_TOLERANCE`` of the start the bridge sends the frames as they are,
so the robot's first step is from there. That step is checked too (at 100
frames per second a 0.45 degree offset is an acceleration over the limit
and a jerk ten times it); if it breaks a limit, the arm approaches first.
"""

from __future__ import annotations

import math

import numpy as np

from bridge.checks import check_frames
from bridge.limits import FrameLimits
from bridge.timeline_keys import is_hand
from bridge.units import unit
from shared.errors import TrajectoryRefusedError
from shared.messages import CommandFrames

#: The arm counts as at the trajectory's start within this much [rad].
START_TOLERANCE = math.radians(0.5)


def needs_approach(
    frames: CommandFrames,
    current: np.ndarray,
    limits: FrameLimits,
    approach: bool,
) -> bool:
    """True if the arm, at ``current`` [rad] (n,), must first move to the start.

    Args:
        frames: Checked frames (from their own start).
        current: Where the arm is commanded to be now [rad], shape (n,).
        limits: The joints' limits.
        approach: Whether an approach move is allowed.

    Raises:
        TrajectoryRefusedError: with ``approach`` False, the arm is away from
            the start, or the frames break a limit counted from where it is.
    """
    start = np.asarray(frames.start)
    gap = np.abs(current - start)
    j = int(np.argmax(gap))
    if gap[j] > START_TOLERANCE:
        if approach:
            return True
        name = frames.joint_names[j]
        raise TrajectoryRefusedError(
            name,
            "start",
            current[j],
            start[j],
            frame=0,
            time=0.0,
            detail=(
                f"is at {current[j]:.4f}{unit(name)}, {_apart(name, gap[j])} "
                f"from the trajectory's start {start[j]:.4f}{unit(name)}, and the "
                "approach move is off"
            ),
        )
    try:
        check_frames(frames.model_copy(update={"start": current.tolist()}), limits)
    except TrajectoryRefusedError as error:
        if approach:
            return True
        raise TrajectoryRefusedError(
            error.joint,
            error.quantity,
            error.value,
            error.limit,
            frame=error.frame,
            time=error.time,
            detail=(
                f"{error.detail}, counted from where the arm is "
                f"({_apart(error.joint, gap[frames.joint_names.index(error.joint)])} "
                "from the trajectory's start), and the approach move is off"
            ),
        ) from None
    return False


def _apart(name: str, gap: float) -> str:
    """How far actuator ``name`` is from the start: degrees, or open fraction."""
    if is_hand(name):
        return f"{gap:.2f} (open fraction)"
    return f"{math.degrees(gap):.2f} deg"
