"""A trajectory as command frames: joint angles at a timeline's frame rate.

And the trajectory's velocities at those frames (:func:`frame_velocities`),
the slopes a Choregraphe behavior's keys are written with.
"""

from __future__ import annotations

import math

import numpy as np

from bridge.hand import with_hand_joint
from bridge.interpolation import positions_at, velocities_at
from shared.errors import InvalidInputError
from shared.messages import CommandFrames, Trajectory
from shared.messages.base import MAX_RATE, MIN_RATE

#: Choregraphe's default timeline frame rate [Hz].
DEFAULT_RATE = 25.0
#: Most frames one trajectory may become: 30 minutes at 25 fps (a planned
#: trajectory is at most 10 minutes). More, sent as one angleInterpolation
#: call, took libqi so long to convert that the robot stopped answering
#: getAngles (100 000 frames to the simulated NAO).
MAX_FRAMES = 45_000


def check_rate(rate: float, what: str = "--rate") -> float:
    """``rate`` [Hz] if a request could name it (``MIN_RATE``..``MAX_RATE``).

    Raises:
        InvalidInputError: out of that range, or not a number, naming ``what``.
    """
    if not MIN_RATE <= rate <= MAX_RATE:  # NaN too
        raise InvalidInputError(
            f"{what} must be a frame rate of {MIN_RATE:g}..{MAX_RATE:g} Hz, got {rate}",
            field="rate",
        )
    return rate


def frame_times(duration: float, rate: float = DEFAULT_RATE) -> np.ndarray:
    """Times of frames 1..m covering ``duration`` [s], shape (m,).

    Frame ``k`` is at ``k / rate``; the last frame is the first one at or
    after the end (at least one frame), so nothing of the movement is cut.

    Args:
        duration: Length of the movement [s].
        rate: Frame rate [Hz].

    Raises:
        InvalidInputError: more than ``MAX_FRAMES`` frames (checked before
            any is made: a trajectory of 1e6 s once filled the memory).
    """
    count = max(1, math.ceil(duration * rate - 1e-9))
    if count > MAX_FRAMES:
        raise InvalidInputError(
            f"a trajectory of {duration:g} s at {rate:g} fps is {count} frames, "
            f"more than {MAX_FRAMES}: lower the frame rate or split the movement",
            field="times",
            frames=count,
            limit=MAX_FRAMES,
        )
    return np.arange(1, count + 1) / rate


def frames_from_trajectory(
    trajectory: Trajectory,
    rate: float = DEFAULT_RATE,
    within: tuple[np.ndarray, np.ndarray] | None = None,
) -> CommandFrames:
    """Sample ``trajectory`` at the frames of a ``rate`` timeline.

    Args:
        trajectory: The trajectory (times from its first sample) [s, rad].
        rate: Frame rate [Hz], Choregraphe's 25 by default.
        within: Joint ranges to hold the curve between samples in (see
            ``bridge.interpolation.positions_at``); only for a trajectory
            whose samples are all within them.

    Returns:
        Frames 1..m at ``k / rate`` [s] with the trajectory's angles there
        [rad], and its first posture as the start (frame 0), held in
        ``within`` as the frames are. A trajectory of one sample gives its
        posture held for one frame: the planner makes one for a task with
        nothing to move and no dwell (the arm stays where it starts,
        docs/planning.md), so it is not refused here; a wrist path of one
        sample, which made one far from the start, is refused where it is
        read (``shared.messages.wrist_path.MIN_SAMPLES``).
    """
    times = frame_times(trajectory.duration, rate)
    start = np.asarray(trajectory.positions[0], dtype=float)
    if within is not None:
        start = np.clip(start, within[0], within[1])
    return CommandFrames(
        arm=trajectory.arm,
        rate=rate,
        joint_names=list(trajectory.joint_names),
        start=start.tolist(),
        times=times.tolist(),
        positions=positions_at(trajectory, times, within).tolist(),
    )


def frame_velocities(trajectory: Trajectory, frames: CommandFrames) -> np.ndarray:
    """The trajectory's velocities at frame 0 and at each frame, shape (m + 1, n).

    The derivative of the curve the frames sample (``bridge.interpolation``:
    the trajectory's own velocities at its samples' times) [rad/s; /s for a
    hand]; 0 after the trajectory's end, where the frames hold its last
    posture. A trajectory with a hand channel gives its hand as the frames
    have it, one more joint (``bridge.hand``).

    Args:
        trajectory: The trajectory the frames were made from.
        frames: Its frames (:func:`frames_from_trajectory`).

    Raises:
        InvalidInputError: the frames move other joints than the trajectory.
    """
    trajectory = with_hand_joint(trajectory)
    if list(trajectory.joint_names) != list(frames.joint_names):
        raise InvalidInputError(
            f"the frames move {frames.joint_names}, the trajectory "
            f"{trajectory.joint_names}: give the trajectory they were made from",
            field="joint_names",
        )
    return velocities_at(trajectory, [0.0, *frames.times])
