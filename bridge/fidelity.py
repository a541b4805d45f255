"""Frames that follow their trajectory: a frame rate too low for it is refused.

The robot goes from key to key (the simulated NAO in straight lines, NAOqi
on its own smooth curve), so between two frames it does not follow the
trajectory. At Choregraphe's 25 Hz the difference is a fraction of a degree;
at a few hertz a movement is cut short (at 1 Hz a 0.3 s wave swing is not
made at all), while every frame still passes the limit checks. The bridge
therefore compares the straight lines between the frames with the
trajectory, at each of its samples and halfway between frames, and refuses
frames that stray from it by more than a degree (or, for a joint as fast as
WristYaw, the gap its acceleration limit makes at 25 fps:
:func:`follow_tolerance`), naming the joint and the time. :func:`offer_rate`
finds a frame rate to offer with the refusal, trying each with the function
that makes and checks the frames to send, so that a rate offered passes every
check (``bridge.checked_frames``).
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np
import numpy.typing as npt

from bridge.frames import DEFAULT_RATE
from bridge.interpolation import positions_at
from bridge.limits import FrameLimits
from bridge.timeline_keys import is_hand
from shared.errors import InvalidInputError, TrajectoryRefusedError
from shared.messages import CommandFrames, Trajectory
from shared.messages.base import MAX_RATE

#: Largest allowed gap between the lines through the frames and the
#: trajectory [rad] (1 degree, the tracking the bridge is held to), unless a
#: joint's own limits allow more (:func:`follow_tolerance`).
FOLLOW_TOLERANCE = math.radians(1.0)
#: Frame rates tried before a refusal suggests one.
ATTEMPTS = 8


def follow_tolerance(limits: FrameLimits) -> np.ndarray:
    """Largest allowed gap of each joint [rad], shape (n,).

    One degree, or the chord gap a joint at its acceleration limit makes
    between frames at Choregraphe's 25 fps (``a T^2 / 8``) if larger, so
    that every trajectory within the bridge's limits passes at 25 fps: the
    fast WristYaw of a ``--fastest`` reach with a palm strays 1.1 degree
    there, within its 2.8.
    """
    chord = np.asarray(limits.acceleration, float) / (8.0 * DEFAULT_RATE**2)
    return np.maximum(FOLLOW_TOLERANCE, chord)


def check_follows(
    frames: CommandFrames,
    trajectory: Trajectory,
    tolerance: npt.ArrayLike,
    within: tuple[np.ndarray, np.ndarray] | None = None,
) -> None:
    """Refuse ``frames`` if the lines between them stray from ``trajectory``.

    Args:
        frames: The trajectory's command frames (``frames_from_trajectory``).
        trajectory: The trajectory [s, rad].
        tolerance: Largest allowed gap [rad], per joint (shape (n,)) or one.
        within: The ranges the frames were held in, if any: the lines are
            compared with the curve held in them, the one the frames are
            sampled from (where the cubic between sparse samples overshoots
            a limit, the frames cannot follow it out of range at any rate).

    Raises:
        TrajectoryRefusedError: quantity ``"frame_rate"``, naming the joint
            and the time of the largest gap [rad] (``value``, against its
            ``limit``); ``offer_rate`` finds a rate to add to it.
    """
    limit = np.broadcast_to(np.asarray(tolerance, float), (len(frames.joint_names),))
    ratio, joint, time, gap = _worst(frames, trajectory, limit, within)
    if ratio <= 1.0:
        return
    frame = int(np.searchsorted(frames.times, time)) + 1
    name = frames.joint_names[joint]
    raise TrajectoryRefusedError(
        name,
        "frame_rate",
        gap,
        limit[joint],
        frame=frame,
        time=time,
        detail=(
            f"would pass {gap_shown(name, gap, '.1f')} from the trajectory at "
            f"t = {time:.3f} s between frames at {frames.rate:g} Hz (at most "
            f"{gap_shown(name, limit[joint], '.3g')})"
        ),
    )


def gap_shown(name: str, gap: float, form: str) -> str:
    """A gap of actuator ``name``: degrees for a joint, open fraction for a hand.

    ``form`` formats the degrees; a gap of a million or more is shown in
    exponent form (a velocity of 1e300 makes one of 1e300 degrees).
    """
    if is_hand(name):
        return f"{gap:{'.3f' if abs(gap) < 1e6 else '.3g'}} (open fraction)"
    degrees = math.degrees(gap)
    return f"{degrees:{form if abs(degrees) < 1e6 else '.3g'}} deg"


def largest_gap(
    frames: CommandFrames,
    trajectory: Trajectory,
    within: tuple[np.ndarray, np.ndarray] | None = None,
) -> tuple[float, int, float]:
    """The largest gap between the lines through ``frames`` and ``trajectory``.

    Args:
        frames: The trajectory's command frames.
        trajectory: The trajectory [s, rad].
        within: The ranges the frames were held in, if any (lower, upper)
            [rad], each shape (n,): the trajectory's curve is held in them too.

    Returns:
        The gap [rad], the index of its joint, and its time from the start [s].
    """
    t, gap = _gaps(frames, trajectory, within)
    i, j = np.unravel_index(int(np.argmax(gap)), gap.shape)
    return float(gap[i, j]), int(j), float(t[i])


def _worst(
    frames: CommandFrames,
    trajectory: Trajectory,
    limit: np.ndarray,
    within: tuple[np.ndarray, np.ndarray] | None = None,
) -> tuple[float, int, float, float]:
    """The gap largest against its joint's limit: (gap / limit, joint, time, gap)."""
    t, gap = _gaps(frames, trajectory, within)
    ratio = gap / limit
    i, j = np.unravel_index(int(np.argmax(ratio)), ratio.shape)
    return float(ratio[i, j]), int(j), float(t[i]), float(gap[i, j])


#: Where between two frames the lines are compared with the curve.
QUARTERS = (0.25, 0.5, 0.75)


def _gaps(
    frames: CommandFrames,
    trajectory: Trajectory,
    within: tuple[np.ndarray, np.ndarray] | None = None,
) -> tuple[np.ndarray, np.ndarray]:
    """Times [s] (k,) and gaps [rad] (k, n) of the lines through the frames.

    At the trajectory's samples and at the quarter points between frames:
    a smooth curve is farthest from a line at its midpoint, but a curve that
    rests at both frames (a cubic with zero end speeds) crosses the line
    there and is farthest at the quarters (at 1 fps, 8.6 degrees passed as
    0). The curve is held in ``within`` as the frames are.
    """
    t_keys = np.concatenate([[0.0], frames.times])
    q_keys = np.vstack([np.asarray(frames.start)[None, :], frames.positions])
    samples = np.asarray(trajectory.times) - trajectory.times[0]
    between = [(1.0 - f) * t_keys[:-1] + f * t_keys[1:] for f in QUARTERS]
    t = np.unique(np.concatenate([samples, *between]))
    lines = np.column_stack(
        [np.interp(t, t_keys, q_keys[:, j]) for j in range(q_keys.shape[1])]
    )
    return t, np.abs(lines - positions_at(trajectory, t, within))


def offer_rate(
    make: Callable[[float], CommandFrames], rate: float, ratio: float
) -> str:
    """A frame rate whose frames pass every check, or why none is offered.

    The gap of straight lines falls about with the square of the frame
    period; starting from that estimate, rates a quarter apart are tried.
    Each is tried with ``make``, the function that makes and checks the
    frames to send, so the rate offered is one whose frames passed: not
    only the gap but every limit, on the frames held in the ranges (above
    the rate refused, a fast movement or a bend where the curve is held at
    a limit can break a speed, acceleration or jerk limit that frames
    further apart keep).

    Args:
        make: Checked frames of the trajectory at a frame rate [Hz]; raises
            ``TrajectoryRefusedError``, or ``InvalidInputError`` for too
            many frames.
        rate: The frame rate refused [Hz].
        ratio: Its largest gap over the gap allowed (> 1).

    Returns:
        "at R Hz it would not", or why no rate is offered.
    """
    for _ in range(ATTEMPTS):
        rate = min(math.ceil(1.25 * rate * math.sqrt(ratio)), MAX_RATE)
        try:
            make(rate)
        except InvalidInputError:
            break  # too many frames at this rate
        except TrajectoryRefusedError as refusal:
            if refusal.quantity != "frame_rate":
                return (
                    f"no frame rate is offered: at {rate:g} Hz {refusal.joint} "
                    f"{refusal.detail}"
                )
            ratio = refusal.value / refusal.limit
        else:
            return f"at {rate:g} Hz it would not"
        if rate >= MAX_RATE:
            break
    return "raise the frame rate"
