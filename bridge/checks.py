"""Check command frames against the joints' limits before anything is sent.

The robot interpolates between keys, so what it is asked to do is the frames
themselves: every frame's angle must lie in its joint's range, the speed
between consecutive frames (frame 0 being the start posture) must stay under
the joint's speed limit, and the second difference of the frames under its
acceleration limit, and the third difference under its jerk limit. Each
difference is a divided difference: k! times it is the k-th derivative of
any smooth curve through the frames somewhere in its window, so a value over
a limit proves the robot cannot pass through those keys within it, however
it interpolates between them. One bad frame refuses the whole trajectory, with a
:class:`~shared.errors.TrajectoryRefusedError` naming the joint, the frame,
its time and the limit.
"""

from __future__ import annotations

import numpy as np

from bridge.limits import FrameLimits
from shared.errors import InvalidInputError, TrajectoryRefusedError
from shared.messages import CommandFrames

#: Slack on every comparison, relative to the limit: float round-off only.
SLACK = 1e-9


def check_frames(frames: CommandFrames, limits: FrameLimits) -> None:
    """Refuse ``frames`` if any of them breaks a limit of ``limits``.

    Raises:
        InvalidInputError: if the frames' joints are not the limits' joints.
        TrajectoryRefusedError: naming the first frame that breaks a position,
            speed, acceleration or jerk limit.
    """
    if tuple(frames.joint_names) != tuple(limits.names):
        raise InvalidInputError(
            f"frames move {list(frames.joint_names)}, expected the joints "
            f"{list(limits.names)}",
            field="joint_names",
        )
    q = np.vstack([np.asarray(frames.start)[None, :], np.asarray(frames.positions)])
    t = np.concatenate([[0.0], frames.times])
    check_positions(q, t, limits)
    velocity = check_speeds(q, t, limits)
    acceleration = check_accelerations(velocity, t, limits)
    check_jerks(acceleration, t, limits)


def _first(mask: np.ndarray) -> tuple[int, int] | None:
    """(frame, joint) of the earliest True in ``mask`` (shape (m, n)), or None."""
    hits = np.argwhere(mask)
    return None if len(hits) == 0 else (int(hits[0][0]), int(hits[0][1]))


def check_positions(q: np.ndarray, t: np.ndarray, limits: FrameLimits) -> None:
    """Every angle in its joint's range.

    Args:
        q: Angles of frames 0..m [rad], shape (m + 1, n).
        t: Their times [s], shape (m + 1,).
        limits: The joints' limits.
    """
    slack = SLACK * np.maximum(1.0, np.abs(limits.upper - limits.lower))
    hit = _first((q < limits.lower - slack) | (q > limits.upper + slack))
    if hit is None:
        return
    k, j = hit
    bound = limits.lower[j] if q[k, j] < limits.lower[j] else limits.upper[j]
    raise TrajectoryRefusedError(
        limits.names[j],
        "position",
        q[k, j],
        bound,
        frame=k,
        time=t[k],
        detail=(
            f"angle {q[k, j]:.4f} rad at frame {k} (t = {t[k]:.3f} s) is outside "
            f"its range [{limits.lower[j]:.4f}, {limits.upper[j]:.4f}] rad"
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
            f"speed {speed:.3f} rad/s from frame {k - 1} (t = {t[k - 1]:.3f} s) "
            f"to frame {k} (t = {t[k]:.3f} s) exceeds its limit "
            f"{limits.velocity[j]:.3f} rad/s"
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
            f"acceleration {value:.2f} rad/s^2 at frame {k} (t = {t[k]:.3f} s) "
            f"exceeds its limit {limits.acceleration[j]:.2f} rad/s^2"
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
            f"jerk {value:.1f} rad/s^3 over frames {k - 2} to {k + 1} (t = "
            f"{t[k - 2]:.3f} to {t[k + 1]:.3f} s) exceeds its limit "
            f"{limits.jerk[j]:.1f} rad/s^3"
        ),
    )
