"""A trajectory as command frames the robot may be sent: every check passed."""

from __future__ import annotations

from functools import partial

from bridge.checks import check_frames, check_sample_range
from bridge.choregraphe import QUANTUM, behavior_frames
from bridge.fidelity import check_follows, follow_tolerance, offer_rate
from bridge.frames import frames_from_trajectory
from bridge.limits import FrameLimits
from shared.errors import TrajectoryRefusedError
from shared.messages import CommandFrames, Trajectory


def checked_frames(
    trajectory: Trajectory, rate: float, limits: FrameLimits
) -> CommandFrames:
    """``trajectory`` as frames at ``rate`` [Hz], checked; nothing is sent.

    The trajectory's own samples must lie in the joints' ranges; the curve
    between them is held in the ranges (a cubic through samples seconds
    apart overshoots a limit the planned path only touches), by a written
    angle's last digit (``QUANTUM``) so no rounding takes it out. The frames
    must keep every limit of ``limits`` (:mod:`bridge.checks`)
    and follow the trajectory between keys within a degree, or a fast
    joint's chord gap at 25 fps (:mod:`bridge.fidelity`). A refusal for a
    frame rate too low offers one whose frames, made and checked here in the
    same way, pass (``bridge.fidelity.offer_rate``).

    Raises:
        InvalidInputError: more frames than the bridge sends in one call,
            or joints other than the limits'.
        TrajectoryRefusedError: naming the first frame that breaks a limit,
            or the joint that strays furthest between frames.
    """
    check_sample_range(trajectory, limits)
    try:
        return _frames_at(trajectory, rate, limits)
    except TrajectoryRefusedError as refusal:
        if refusal.quantity != "frame_rate":
            raise
        make = partial(_frames_at, trajectory, limits=limits)
        advice = offer_rate(make, rate, refusal.value / refusal.limit)
        raise refusal.adding(f": {advice}") from None


def _frames_at(
    trajectory: Trajectory, rate: float, limits: FrameLimits
) -> CommandFrames:
    """Frames at ``rate`` [Hz] held in the ranges, checked (see above)."""
    inside = (limits.lower + QUANTUM, limits.upper - QUANTUM)
    frames = frames_from_trajectory(trajectory, rate, inside)
    check_frames(frames, limits)
    check_follows(frames, trajectory, follow_tolerance(limits), inside)
    return frames


def check_behavior(frames: CommandFrames, limits: FrameLimits) -> None:
    """Refuse ``frames`` if they break a limit as a Choregraphe behavior plays them.

    The keys the behavior's timeline holds (``bridge.timeline_keys``): the
    start posture at 0 s, frame ``k`` at ``k / rate``, the last posture
    held; each angle rounded to ``DECIMALS`` in degrees.

    Raises:
        TrajectoryRefusedError: naming the first frame that breaks a limit.
    """
    check_frames(behavior_frames(frames), limits)
