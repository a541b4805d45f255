"""Frames that follow their trajectory: a frame rate too low for it is refused.

The robot goes from key to key (the simulated NAO in straight lines, NAOqi
on its own smooth curve), so between two frames it does not follow the
trajectory. At Choregraphe's 25 Hz the difference is a fraction of a degree;
at a few hertz a movement is cut short (at 1 Hz a 0.3 s wave swing is not
made at all), while every frame still passes the limit checks. The bridge
therefore compares the straight lines between the frames with the
trajectory, at each of its samples and halfway between frames, and refuses
frames that stray from it by more than :data:`FOLLOW_TOLERANCE`, naming the
joint, the time and a frame rate that would do.
"""

from __future__ import annotations

import math

import numpy as np

from bridge.frames import frames_from_trajectory
from bridge.interpolation import positions_at
from shared.errors import InvalidInputError, TrajectoryRefusedError
from shared.messages import CommandFrames, Trajectory
from shared.messages.base import MAX_RATE

#: Largest allowed gap between the lines through the frames and the
#: trajectory [rad] (1 degree, the tracking the bridge is held to).
FOLLOW_TOLERANCE = math.radians(1.0)
#: Frame rates tried before a refusal suggests one.
ATTEMPTS = 8


def check_follows(
    frames: CommandFrames,
    trajectory: Trajectory,
    tolerance: float = FOLLOW_TOLERANCE,
) -> None:
    """Refuse ``frames`` if the lines between them stray from ``trajectory``.

    Args:
        frames: The trajectory's command frames (``frames_from_trajectory``).
        trajectory: The trajectory [s, rad].
        tolerance: Largest allowed gap [rad].

    Raises:
        TrajectoryRefusedError: quantity ``"frame_rate"``, naming the joint
            and the time of the largest gap [rad] and a rate that would do.
    """
    gap, joint, time = largest_gap(frames, trajectory)
    if gap <= tolerance:
        return
    frame = int(np.searchsorted(frames.times, time)) + 1
    raise TrajectoryRefusedError(
        frames.joint_names[joint],
        "frame_rate",
        gap,
        tolerance,
        frame=frame,
        time=time,
        detail=(
            f"would pass {math.degrees(gap):.1f} deg from the trajectory at "
            f"t = {time:.3f} s between frames at {frames.rate:g} Hz (at most "
            f"{math.degrees(tolerance):g} deg): "
            + _advice(trajectory, frames.rate, gap, tolerance)
        ),
    )


def largest_gap(
    frames: CommandFrames, trajectory: Trajectory
) -> tuple[float, int, float]:
    """The largest gap between the lines through ``frames`` and ``trajectory``.

    Returns:
        The gap [rad], the index of its joint, and its time from the start [s].
    """
    t_keys = np.concatenate([[0.0], frames.times])
    q_keys = np.vstack([np.asarray(frames.start)[None, :], frames.positions])
    samples = np.asarray(trajectory.times) - trajectory.times[0]
    t = np.unique(np.concatenate([samples, 0.5 * (t_keys[1:] + t_keys[:-1])]))
    lines = np.column_stack(
        [np.interp(t, t_keys, q_keys[:, j]) for j in range(q_keys.shape[1])]
    )
    gap = np.abs(lines - positions_at(trajectory, t))  # (k, n)
    i, j = np.unravel_index(int(np.argmax(gap)), gap.shape)
    return float(gap[i, j]), int(j), float(t[i])


def _advice(trajectory: Trajectory, rate: float, gap: float, tolerance: float) -> str:
    """A frame rate that passes, found by trying, or why none is offered.

    The gap of straight lines falls about with the square of the frame
    period; starting from that estimate, rates a quarter apart are tried.
    """
    for _ in range(ATTEMPTS):
        rate = min(math.ceil(1.25 * rate * math.sqrt(gap / tolerance)), MAX_RATE)
        try:
            frames = frames_from_trajectory(trajectory, rate)
        except InvalidInputError:
            break  # too many frames at this rate
        gap = largest_gap(frames, trajectory)[0]
        if gap <= tolerance:
            return f"at {rate:g} Hz it would not"
        if rate >= MAX_RATE:
            break
    return "raise the frame rate"
