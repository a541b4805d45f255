"""The hand (gripper) as one more joint of the frames the bridge checks and sends.

A trajectory with a hand channel (``Trajectory.hand``: the open fraction
0..1 at each sample) is played as if the hand were a sixth joint named
``RHand`` (``LHand``): NAOqi's ``angleInterpolation`` takes it beside the
arm's joints in the same call, its value the open fraction, and a
Choregraphe timeline holds it as one more actuator curve (``unit="1"``:
the value as written, no degrees). So the frames, every check (range 0..1,
speed, acceleration and jerk against the hand's limits: ``FrameLimits.
with_hand``), the approach to the start, the behavior and the Python export
all take it as they take a joint.

The hand's curve between samples is the cubic Hermite curve the joints'
is, through the planner's hand speeds (``Trajectory.hand_velocities``) as
the joints' goes through theirs: a move the planner kept within the hand's
limits keeps them between samples too, at any frame rate. A trajectory
that carries no hand speeds gets the channel's central differences, which
kink where a move leaves or reaches a rest (a 100 Hz plan's hand, so
interpolated, had 18 times its planned jerk between samples and was
refused at 500 and 1000 fps).
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from bridge.limits import FrameLimits
from bridge.timeline_keys import is_hand
from shared.errors import InvalidInputError
from shared.messages import Trajectory


def with_hand_joint(trajectory: Trajectory) -> Trajectory:
    """``trajectory`` with its hand channel as one more joint, after the arm's.

    Returns it unchanged if it has no hand channel.

    Raises:
        InvalidInputError: its joints already hold a hand.
    """
    if trajectory.hand is None:
        return trajectory
    name = trajectory.arm.hand_joint
    if any(is_hand(joint) for joint in trajectory.joint_names):
        raise InvalidInputError(
            f"the trajectory has a hand channel and a joint named like a hand "
            f"among {trajectory.joint_names}: give the hand once, as its channel",
            field="joint_names",
        )
    t = np.asarray(trajectory.times, dtype=float)
    hand = np.asarray(trajectory.hand, dtype=float)
    speed = _given(trajectory.hand_velocities, lambda: _derivative(hand, t))
    change = _given(trajectory.hand_accelerations, lambda: _derivative(speed, t))
    return trajectory.model_copy(
        update={
            "joint_names": [*trajectory.joint_names, name],
            "positions": _joined(trajectory.positions, hand),
            "velocities": _joined(trajectory.velocities, speed),
            "accelerations": _joined(trajectory.accelerations, change),
            "hand": None,
            "hand_velocities": None,
            "hand_accelerations": None,
        }
    )


def with_hand(
    trajectory: Trajectory, limits: FrameLimits
) -> tuple[Trajectory, FrameLimits]:
    """``trajectory`` with its hand as a joint, and ``limits`` with the hand's.

    Both unchanged for a trajectory without a hand channel.
    """
    if trajectory.hand is None:
        return trajectory, limits
    return with_hand_joint(trajectory), limits.with_hand(trajectory.arm)


def hand_inside(trajectory: Trajectory, inset: float) -> Trajectory:
    """``trajectory`` with its hand joints' open fraction held in 0..1 by ``inset``.

    Mapped affinely onto ``inset``..``1 - inset`` (speeds and accelerations
    scaled alike), not clipped: the hand rests at 0 or 1, and a curve
    clipped there kinks where it leaves the rest (at 1000 fps a jerk of
    2107 /s^3, over the hand's 1666, from a move within 666). Unchanged if
    it has no hand joint.

    Args:
        trajectory: A trajectory whose hand is a joint (:func:`with_hand_joint`).
        inset: How far inside 0..1 to hold it [-].
    """
    columns = [k for k, name in enumerate(trajectory.joint_names) if is_hand(name)]
    if not columns:
        return trajectory
    scale = 1.0 - 2.0 * inset
    rows = {}
    for field, offset in (
        ("positions", inset),
        ("velocities", 0.0),
        ("accelerations", 0.0),
    ):
        values = np.asarray(getattr(trajectory, field), dtype=float)
        values[:, columns] = offset + scale * values[:, columns]
        rows[field] = values.tolist()
    return trajectory.model_copy(update=rows)


def _given(
    values: list[float] | None, otherwise: Callable[[], np.ndarray]
) -> np.ndarray:
    """``values`` as an array, shape (n,), or ``otherwise()`` if None."""
    return otherwise() if values is None else np.asarray(values, dtype=float)


def _derivative(values: np.ndarray, t: np.ndarray) -> np.ndarray:
    """d values / dt by central differences (one-sided at the ends), shape (n,)."""
    if len(values) < 2:
        return np.zeros_like(values)
    return np.gradient(values, t)


def _joined(rows: list[list[float]], column: np.ndarray) -> list[list[float]]:
    """``rows`` (n, k) with ``column`` (n,) as one more value each: (n, k + 1)."""
    return np.column_stack([np.asarray(rows, dtype=float), column]).tolist()
