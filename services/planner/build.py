"""The planner's result messages from the algorithms' arrays."""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING

import numpy as np

from services.ik.kernel.chain import chain_for
from services.ik.palm_reached import palm_reached
from services.ik.track import TrackedPath
from services.ik.wrists import wrist_positions
from shared.messages import JointPath, Method, PalmReached, Trajectory
from shared.robot.arm_model import ArmModel

if TYPE_CHECKING:  # the timing package loads scipy.interpolate (about 0.7 s),
    # which the IK and decide services, importing this module, never use
    from services.timing import TimedTrajectory


def joint_path_message(
    arm: ArmModel, times: Sequence[float], tracked: TrackedPath
) -> JointPath:
    """The ``JointPath`` of a tracked wrist path (one row per path point)."""
    return JointPath(
        arm=arm.side,
        joint_names=list(arm.joint_names),
        times=list(times),
        positions=tracked.q.tolist(),
        primitives=list(tracked.labels),
        wrist=[tuple(w) for w in tracked.wrist.tolist()],
    )


def trajectory_message(
    arm: ArmModel,
    joint_paths: Sequence[JointPath],
    timed: TimedTrajectory,
    method: Method,
) -> Trajectory:
    """The ``Trajectory`` of timed joint paths joined end to start.

    Each sample takes the primitive of the path point it is at (its
    ``path_index`` rounded down) and the wrist position of its own joint
    angles (forward kinematics of ``arm``), not of the IK path there: the
    timing's curve between two path points is not the IK's. Path points are
    numbered along the joined paths, the point where two paths meet counted
    once (the timing stage's numbering).
    """
    labels: list[str] = []
    for k, path in enumerate(joint_paths):
        labels.extend(path.primitives[1 if k else 0 :])
    index = np.clip(timed.path_index, 0.0, len(labels) - 1.0)
    wrist = wrist_positions(chain_for(arm), timed.positions)
    first = joint_paths[0]
    return Trajectory(
        arm=first.arm,
        joint_names=list(first.joint_names),
        times=timed.times.tolist(),
        positions=timed.positions.tolist(),
        velocities=timed.velocities.tolist(),
        accelerations=timed.accelerations.tolist(),
        primitives=[labels[i] for i in np.floor(index).astype(int)],
        wrist_path=[tuple(w) for w in wrist.tolist()],
        method=method,
    )


def with_palms_reached(
    arm: ArmModel,
    trajectory: Trajectory,
    palms: Sequence[Sequence[float] | None],
    postures: Sequence[Sequence[float]],
) -> Trajectory:
    """``trajectory`` with the palm reached where one was asked (``palm_reached``).

    Args:
        arm: The arm.
        trajectory: The planned trajectory.
        palms: The palm direction asked at each target (or along the wrist
            path), ``None`` where none was.
        postures: The posture at each of them [rad], shape (len(palms), 5).

    Returns:
        ``trajectory`` itself when no palm was asked.
    """
    if all(palm is None for palm in palms):
        return trajectory
    reached: list[PalmReached | None] = [
        None if palm is None else palm_reached(arm, q, palm)
        for palm, q in zip(palms, postures, strict=True)
    ]
    return trajectory.model_copy(update={"palm_reached": reached})


def arc_length(wrist: Sequence[Sequence[float]]) -> np.ndarray:
    """Cumulative length of a wrist path [m], shape (n,), from 0."""
    points = np.asarray(wrist, dtype=float)
    steps = np.linalg.norm(np.diff(points, axis=0), axis=1)
    return np.concatenate(([0.0], np.cumsum(steps)))
