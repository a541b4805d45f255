"""Check command frames against the joints' limits before anything is sent.

The robot interpolates between keys, so what it is asked to do is the frames
themselves: every frame's angle must lie in its joint's range, the speed
between consecutive frames (frame 0 being the start posture) must stay under
the joint's speed limit, and the second difference of the frames under its
acceleration limit, and the third difference under its jerk limit. Each
difference is a divided difference: k! times it is the k-th derivative of
any smooth curve through the frames somewhere in its window, so a value over
a limit proves that no curve through those keys keeps it. The converse does
not hold: keys that pass can still be joined by a curve that breaks a limit
between them (Choregraphe's BezierAuto curve asked 1.2 times the
acceleration limit of a reach whose keys passed), so a behavior is checked
on the curve its runtime plays too (``bridge.bezier_curve``); how ALMotion's
``angleInterpolation`` joins keys is its own. The arm is at rest before
frame 0 and after the last frame (the robot holds its last key), so the
acceleration and jerk of starting from rest and of coming to rest are
checked too (:func:`check_rest_ends`): a trajectory that sets off at speed
is a step the robot cannot make. One bad frame refuses the whole trajectory, with a
:class:`~shared.errors.TrajectoryRefusedError` naming the joint, the frame,
its time and the limit.
"""

from __future__ import annotations

import numpy as np

from bridge.float32 import held
from bridge.limits import FrameLimits
from bridge.units import unit, value_name
from shared.errors import InvalidInputError, TrajectoryRefusedError, fixed
from shared.messages import CommandFrames, Trajectory

#: Slack on every comparison, relative to the limit: float round-off only.
SLACK = 1e-9
#: What a refusal of the frames as NAOqi holds them (32 bits) adds to its
#: detail: the 64-bit frames passed (``bridge.held_rate`` offers a rate).
HELD_WORDS = (
    " (with the angles and times rounded to 32-bit floats, as NAOqi "
    "holds them; frames further apart suffer less from it)"
)
#: Frames of rest seen before frame 0 and after the last frame: enough for
#: every jerk window (four frames) that reaches into the rest.
REST = 2


def check_frames(
    frames: CommandFrames, limits: FrameLimits, *, as_held: bool = True
) -> None:
    """Refuse ``frames`` if any of them breaks a limit of ``limits``.

    The frames are checked as given, and (``as_held``, what the robot is
    sent) as NAOqi holds them: every angle and time rounded to 32 bits
    (``bridge.float32``), which at 900 fps made a jerk over the limit that
    the 64-bit frames kept.

    Raises:
        InvalidInputError: if the frames' joints are not the limits' joints.
        TrajectoryRefusedError: naming the first frame that breaks a position,
            speed, acceleration or jerk limit.
    """
    check_joints(frames.joint_names, limits, "frames")
    q = np.vstack([np.asarray(frames.start)[None, :], np.asarray(frames.positions)])
    t = np.concatenate([[0.0], frames.times])
    _check_rows(q, t, 1.0 / frames.rate, limits)
    q32, t32 = held(q), held(t)
    if not as_held or (np.array_equal(q32, q) and np.array_equal(t32, t)):
        return
    try:
        _check_rows(q32, t32, 1.0 / frames.rate, limits)
    except TrajectoryRefusedError as refusal:
        raise refusal.adding(HELD_WORDS) from None


def refused_as_held(refusal: TrajectoryRefusedError) -> bool:
    """Whether :func:`check_frames` refused frames only as NAOqi holds them."""
    return refusal.detail.endswith(HELD_WORDS)


def _check_rows(
    q: np.ndarray, t: np.ndarray, period: float, limits: FrameLimits
) -> None:
    """Every check of :func:`check_frames` on frames 0..m.

    Args:
        q: Angles of frames 0..m [rad], shape (m + 1, n).
        t: Their times [s], shape (m + 1,).
        period: Time between frames of rest before and after [s].
        limits: The joints' limits.
    """
    check_positions(q, t, limits)
    velocity = check_speeds(q, t, limits)
    acceleration = check_accelerations(velocity, t, limits)
    check_jerks(acceleration, t, limits)
    check_rest_ends(q, t, period, limits)


def check_joints(
    names: list[str], limits: FrameLimits, what: str = "the trajectory"
) -> None:
    """``names`` are the limits' joints, in their order.

    Raises:
        InvalidInputError: naming what moves which joints, and the expected.
    """
    if tuple(names) != tuple(limits.names):
        raise InvalidInputError(
            f"{what} move{'' if what == 'frames' else 's'} {_names(names)}, "
            f"expected the joints {list(limits.names)}",
            field="joint_names",
        )


def _names(names: list[str], shown: int = 6) -> str:
    """``names`` for a message: the first ``shown`` and how many in all."""
    if len(names) <= shown:
        return str(list(names))
    head = ", ".join(repr(name) for name in names[:shown])
    return f"[{head}, ...] ({len(names)} joints)"


def _first(mask: np.ndarray) -> tuple[int, int] | None:
    """(frame, joint) of the earliest True in ``mask`` (shape (m, n)), or None."""
    hits = np.argwhere(mask)
    return None if len(hits) == 0 else (int(hits[0][0]), int(hits[0][1]))


def check_sample_range(trajectory: Trajectory, limits: FrameLimits) -> None:
    """Every sample of ``trajectory`` in its joint's range (named as a sample).

    Raises:
        InvalidInputError: if the trajectory's joints are not the limits'.
        TrajectoryRefusedError: naming the first sample out of range.
    """
    check_joints(trajectory.joint_names, limits)
    t = np.asarray(trajectory.times, dtype=float)
    q = np.asarray(trajectory.positions, dtype=float)
    check_positions(q, t - t[0], limits, what="sample")


def outside_range(q: np.ndarray, limits: FrameLimits) -> np.ndarray:
    """Which angles of ``q`` [rad] (..., n) are out of range, with ``SLACK``."""
    slack = SLACK * np.maximum(1.0, np.abs(limits.upper - limits.lower))
    return (q < limits.lower - slack) | (q > limits.upper + slack)


def check_positions(
    q: np.ndarray, t: np.ndarray, limits: FrameLimits, what: str = "frame"
) -> None:
    """Every angle in its joint's range.

    Args:
        q: Angles of frames 0..m [rad], shape (m + 1, n).
        t: Their times [s], shape (m + 1,).
        limits: The joints' limits.
        what: What a row is called in the message (``frame`` or ``sample``).
    """
    hit = _first(outside_range(q, limits))
    if hit is None:
        return
    k, j = hit
    name = limits.names[j]
    bound = limits.lower[j] if q[k, j] < limits.lower[j] else limits.upper[j]
    raise TrajectoryRefusedError(
        limits.names[j],
        "position",
        q[k, j],
        bound,
        frame=k,
        time=t[k],
        detail=(
            f"{value_name(name)} {fixed(q[k, j], 4)}{unit(name)} at {what} {k} "
            f"(t = {t[k]:.3f} s) is outside its range "
            f"[{limits.lower[j]:.4f}, {limits.upper[j]:.4f}]{unit(name)}"
        ),
    )


def check_speeds(q: np.ndarray, t: np.ndarray, limits: FrameLimits) -> np.ndarray:
    """Speed between consecutive frames under each joint's speed limit.

    Args:
        q: Angles of frames 0..m [rad], shape (m + 1, n).
        t: Their times [s], shape (m + 1,).
        limits: The joints' limits.

    Returns:
        Speed from frame k-1 to frame k, for k = 1..m [rad/s], shape (m, n).
    """
    velocity = np.diff(q, axis=0) / np.diff(t)[:, None]
    hit = _first(np.abs(velocity) > limits.velocity * (1.0 + SLACK))
    if hit is None:
        return velocity
    k, j = hit[0] + 1, hit[1]
    speed = abs(velocity[k - 1, j])
    raise TrajectoryRefusedError(
        limits.names[j],
        "velocity",
        speed,
        limits.velocity[j],
        frame=k,
        time=t[k],
        detail=(
            f"speed {fixed(speed, 3)}{unit(limits.names[j], 1)} from frame {k - 1} "
            f"(t = {t[k - 1]:.3f} s) "
            f"to frame {k} (t = {t[k]:.3f} s) exceeds its limit "
            f"{limits.velocity[j]:.3f}{unit(limits.names[j], 1)}"
        ),
    )


def check_accelerations(
    velocity: np.ndarray, t: np.ndarray, limits: FrameLimits
) -> np.ndarray:
    """Change of speed at each frame under each joint's acceleration limit.

    Args:
        velocity: Speed from frame k-1 to frame k, k = 1..m [rad/s], (m, n).
        t: Times of frames 0..m [s], shape (m + 1,).
        limits: The joints' limits.

    Returns:
        Acceleration over frames k-1..k+1, at frame k = 1..m-1 [rad/s^2],
        shape (m - 1, n) (empty with fewer than two speeds).
    """
    if len(velocity) < 2:
        return np.zeros((0, velocity.shape[1]))
    span = 0.5 * (t[2:] - t[:-2])
    accel = np.diff(velocity, axis=0) / span[:, None]
    hit = _first(np.abs(accel) > limits.acceleration * (1.0 + SLACK))
    if hit is None:
        return accel
    k, j = hit[0] + 1, hit[1]
    value = abs(accel[k - 1, j])
    raise TrajectoryRefusedError(
        limits.names[j],
        "acceleration",
        value,
        limits.acceleration[j],
        frame=k,
        time=t[k],
        detail=(
            f"acceleration {fixed(value, 2)}{unit(limits.names[j], 2)} at frame {k} "
            f"(t = {t[k]:.3f} s) exceeds its limit "
            f"{limits.acceleration[j]:.2f}{unit(limits.names[j], 2)}"
        ),
    )


def check_jerks(accel: np.ndarray, t: np.ndarray, limits: FrameLimits) -> None:
    """Change of acceleration under each joint's jerk limit.

    Args:
        accel: Acceleration over frames k-1..k+1, k = 1..m-1 [rad/s^2],
            shape (m - 1, n), as :func:`check_accelerations` returns it.
        t: Times of frames 0..m [s], shape (m + 1,).
        limits: The joints' limits.

    The jerk over frames k-2..k+1 (six times their third divided
    difference) is reported at frame k.
    """
    if len(accel) < 2:
        return
    span = (t[3:] - t[:-3]) / 3.0
    jerk = np.diff(accel, axis=0) / span[:, None]
    hit = _first(np.abs(jerk) > limits.jerk * (1.0 + SLACK))
    if hit is None:
        return
    k, j = hit[0] + 2, hit[1]
    value = abs(jerk[k - 2, j])
    raise TrajectoryRefusedError(
        limits.names[j],
        "jerk",
        value,
        limits.jerk[j],
        frame=k,
        time=t[k],
        detail=(
            f"jerk {fixed(value, 1)}{unit(limits.names[j], 3)} over frames {k - 2} "
            f"to {k + 1} (t = "
            f"{t[k - 2]:.3f} to {t[k + 1]:.3f} s) exceeds its limit "
            f"{limits.jerk[j]:.1f}{unit(limits.names[j], 3)}"
        ),
    )


def check_rest_ends(
    q: np.ndarray, t: np.ndarray, period: float, limits: FrameLimits
) -> None:
    """Starting from rest and coming to rest within the acceleration and jerk limits.

    The frames are seen with ``REST`` frames of the start posture before
    frame 0 and of the last posture after the last frame, ``period`` apart;
    only the windows that reach into that rest are checked here (the others
    were, by :func:`check_accelerations` and :func:`check_jerks`).

    Args:
        q: Angles of frames 0..m [rad], shape (m + 1, n).
        t: Their times [s], shape (m + 1,).
        period: Time between frames [s].
        limits: The joints' limits.
    """
    m = len(q) - 1
    before = t[0] - period * np.arange(REST, 0, -1)
    after = t[-1] + period * np.arange(1, REST + 1)
    tp = np.concatenate([before, t, after])
    qp = np.vstack([np.repeat(q[:1], REST, axis=0), q, np.repeat(q[-1:], REST, axis=0)])
    velocity = np.diff(qp, axis=0) / np.diff(tp)[:, None]
    accel = np.diff(velocity, axis=0) / (0.5 * (tp[2:] - tp[:-2]))[:, None]
    jerk = np.diff(accel, axis=0) / ((tp[3:] - tp[:-3]) / 3.0)[:, None]
    for quantity, values, bound, width in (
        ("acceleration", accel, limits.acceleration, 3),
        ("jerk", jerk, limits.jerk, 4),
    ):
        first = np.arange(len(values))  # each window's first padded frame
        touches = (first < REST) | (first + width - 1 > REST + m)
        hit = _first(touches[:, None] & (np.abs(values) > bound * (1.0 + SLACK)))
        if hit is not None:
            _refuse_at_rest(
                quantity, values, bound, hit, first[hit[0]] < REST, t, limits
            )


def _refuse_at_rest(
    quantity: str,
    values: np.ndarray,
    bound: np.ndarray,
    hit: tuple[int, int],
    starting: bool,
    t: np.ndarray,
    limits: FrameLimits,
) -> None:
    """Raise for ``values[hit]`` over ``bound`` when starting or coming to rest."""
    i, j = hit
    frame = 0 if starting else len(t) - 1
    per = unit(limits.names[j], 2 if quantity == "acceleration" else 3)
    when = (
        "setting off from rest at frame 0"
        if starting
        else f"coming to rest at frame {frame}"
    )
    value = abs(values[i, j])
    raise TrajectoryRefusedError(
        limits.names[j],
        quantity,
        value,
        bound[j],
        frame=frame,
        time=t[frame],
        detail=(
            f"{quantity} {fixed(value, 1)}{per} {when} (t = {t[frame]:.3f} s; the "
            "arm rests before the first frame and after the last) exceeds its limit "
            f"{bound[j]:.1f}{per}"
        ),
    )
