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
is; its slopes are the hand channel's central differences (the trajectory
carries no hand speeds).
"""

from __future__ import annotations

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
    speed = _derivative(hand, t)
    return trajectory.model_copy(
        update={
            "joint_names": [*trajectory.joint_names, name],
            "positions": _joined(trajectory.positions, hand),
            "velocities": _joined(trajectory.velocities, speed),
            "accelerations": _joined(trajectory.accelerations, _derivative(speed, t)),
            "hand": None,
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


def _derivative(values: np.ndarray, t: np.ndarray) -> np.ndarray:
    """d values / dt by central differences (one-sided at the ends), shape (n,)."""
    if len(values) < 2:
        return np.zeros_like(values)
    return np.gradient(values, t)


def _joined(rows: list[list[float]], column: np.ndarray) -> list[list[float]]:
    """``rows`` (n, k) with ``column`` (n,) as one more value each: (n, k + 1)."""
    return np.column_stack([np.asarray(rows, dtype=float), column]).tolist()
