"""A trajectory as command frames the robot may be sent: every check passed."""

from __future__ import annotations

from collections.abc import Callable
from functools import partial

import numpy.typing as npt

from bridge.bezier_curve import check_played_curve, played_curve
from bridge.body_clearance import check_frames_clear, check_trajectory_clear
from bridge.checks import check_frames, check_sample_range, refused_as_held
from bridge.fidelity import ATTEMPTS, check_follows, follow_tolerance, offer_rate
from bridge.frames import frame_velocities, frames_from_trajectory
from bridge.hand import hand_inside, with_hand
from bridge.held_rate import held_advice
from bridge.limits import FrameLimits
from bridge.timeline_keys import KEY_INSET, played_frames, timeline_keys
from bridge.velocity_agreement import check_velocities
from shared.errors import InvalidInputError, TrajectoryRefusedError
from shared.messages import CommandFrames, Trajectory

#: Frame rates tried, nearest the one refused first, when a behavior's
#: curve breaks a limit [Hz]: whole rates, Choregraphe's 25 among them.
BEHAVIOR_RATES = (10, 15, 20, 25, 30, 40, 50, 100)


def checked_frames(
    trajectory: Trajectory,
    rate: float,
    limits: FrameLimits,
    *,
    behavior: bool = False,
) -> CommandFrames:
    """``trajectory`` as frames at ``rate`` [Hz], checked; nothing is sent.

    The trajectory's own samples must lie in the joints' ranges, keep the
    arm clear of NAO's body (:mod:`bridge.body_clearance`), as must the
    frames, and its
    velocities agree with its positions (the curve through both within a
    degree, or a fast joint's chord gap at 25 fps, of the positions' own:
    :mod:`bridge.velocity_agreement`); the curve
    between them is held in the ranges (a cubic through samples seconds
    apart overshoots a limit the planned path only touches), by
    ``bridge.timeline_keys.KEY_INSET`` (a written angle's last digit or the
    rounding to 32 bits on the way to the robot, whichever is more), so no
    rounding takes it out. The frames
    must keep every limit of ``limits`` (:mod:`bridge.checks`)
    and follow the trajectory between keys within a degree, or a fast
    joint's chord gap at 25 fps (:mod:`bridge.fidelity`). A refusal for a
    frame rate too low offers one whose frames, made and checked here in the
    same way, pass (``bridge.fidelity.offer_rate``); so does a refusal of
    frames too close for their 32-bit times (``bridge.held_rate``), with a
    lower rate. A trajectory's hand
    channel is one more joint of the frames, after the arm's, held to the
    hand's range and limits (``bridge.hand``).

    Args:
        trajectory: The trajectory [s, rad].
        rate: Frame rate [Hz].
        limits: The arm's joints' limits (the hand's are added for a
            trajectory with a hand channel).
        behavior: Also check the frames as a Choregraphe behavior plays
            them (:func:`check_behavior`, the keys' tangents the
            trajectory's velocities: ``bridge.frames.frame_velocities``),
            for a behavior file written with those velocities; a rate
            offered then passes that check too, and a refusal of the
            behavior's curve offers a whole rate whose behavior passes.

    Raises:
        InvalidInputError: more frames than the bridge sends in one call,
            joints other than the limits', or (``behavior``) a rate that is
            no whole number.
        TrajectoryRefusedError: naming the first frame that breaks a limit,
            the joint that strays furthest between frames, or the sample
            whose velocity disagrees most with the positions.
    """
    given, arm = trajectory, limits
    trajectory, limits = with_hand(trajectory, limits)
    check_sample_range(trajectory, limits)
    check_velocities(given, arm)
    check_trajectory_clear(given)
    make = partial(_frames_at, trajectory, limits=limits, behavior=behavior)
    try:
        frames = _frames_at(trajectory, rate, limits)
    except TrajectoryRefusedError as refusal:
        if refused_as_held(refusal):
            raise refusal.adding(f": {held_advice(make, rate)}") from None
        if refusal.quantity != "frame_rate":
            raise
        advice = offer_rate(make, rate, refusal.value / refusal.limit)
        raise refusal.adding(f": {advice}") from None
    if behavior:
        try:
            check_behavior(frames, limits, frame_velocities(trajectory, frames))
        except TrajectoryRefusedError as refusal:
            raise refusal.adding(f": {_behavior_advice(make, rate)}") from None
    return frames


def _frames_at(
    trajectory: Trajectory, rate: float, limits: FrameLimits, behavior: bool = False
) -> CommandFrames:
    """Frames at ``rate`` [Hz] held in the ranges, checked (see above)."""
    inside = (limits.lower + KEY_INSET, limits.upper - KEY_INSET)
    frames = frames_from_trajectory(hand_inside(trajectory, KEY_INSET), rate, inside)
    check_frames(frames, limits)
    check_follows(frames, trajectory, follow_tolerance(limits), inside)
    check_frames_clear(frames)
    if behavior:
        check_behavior(frames, limits, frame_velocities(trajectory, frames))
    return frames


def _behavior_advice(make: Callable[[float], CommandFrames], rate: float) -> str:
    """A whole frame rate whose behavior passes every check, or what to do.

    The curve Choregraphe plays is cubic between keys, so another rate
    gives another curve (not always a gentler one): the rates of
    ``BEHAVIOR_RATES`` nearest ``rate`` are tried, each made and checked by
    ``make`` as the frames written would be.
    """
    tried = sorted(
        (r for r in BEHAVIOR_RATES if r != rate), key=lambda r: abs(r - rate)
    )
    for candidate in tried[:ATTEMPTS]:
        try:
            make(candidate)
        except (TrajectoryRefusedError, InvalidInputError):
            continue
        return f"at {candidate} fps it would not"
    return (
        "no frame rate is offered: plan the movement slower (lower "
        "accelerations and jerks), or export it as Python (angleInterpolation, "
        "as the bridge plays it)"
    )


def check_behavior(
    frames: CommandFrames, limits: FrameLimits, velocities: npt.ArrayLike
) -> None:
    """Refuse ``frames`` if they break a limit as a Choregraphe behavior plays them.

    The keys the behavior's timeline holds (``bridge.timeline_keys``): the
    start posture at 0 s, frame ``k`` at ``k / rate``, the last posture
    held; each angle rounded to ``DECIMALS`` in degrees, each key's
    tangents made from ``velocities``. The keys must pass
    :func:`bridge.checks.check_frames`, and the curve the runtime plays
    through them and their tangents (:mod:`bridge.bezier_curve`) every
    range, speed, acceleration and jerk limit.

    Args:
        frames: The frames.
        limits: Their joints' limits.
        velocities: The trajectory's velocities at frame 0 and each frame
            [rad/s], shape (m + 1, n) (``bridge.frames.frame_velocities``),
            as the behavior is written with them.

    Raises:
        InvalidInputError: the rate is not a whole number, or ``velocities``
            not one row per key.
        TrajectoryRefusedError: naming the first frame that breaks a limit.
    """
    keys = timeline_keys(frames, velocities)
    check_frames(played_frames(keys, frames), limits)
    check_played_curve(played_curve(keys), limits)
