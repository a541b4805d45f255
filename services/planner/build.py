"""The planner's result messages from the algorithms' arrays."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from services.ik.track import TrackedPath
from services.timing import TimedTrajectory
from shared.messages import JointPath, Method, Trajectory
from shared.robot.arm_model import ArmModel


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
    joint_paths: Sequence[JointPath], timed: TimedTrajectory, method: Method
) -> Trajectory:
    """The ``Trajectory`` of timed joint paths joined end to start.

    Each sample takes the primitive of the path point it is at (its
    ``path_index`` rounded down) and the wrist position of the IK path there,
    interpolated linearly between the two path points it lies between.
    Path points are numbered along the joined paths, the point where two
    paths meet counted once (the timing stage's numbering).
    """
    labels: list[str] = []
    wrist: list[np.ndarray] = []
    for k, path in enumerate(joint_paths):
        skip = 1 if k else 0
        labels.extend(path.primitives[skip:])
        wrist.append(np.asarray(path.wrist, dtype=float)[skip:])
    points = np.vstack(wrist)
    index = np.clip(timed.path_index, 0.0, len(points) - 1.0)
    low = np.minimum(np.floor(index).astype(int), len(points) - 2)
    frac = (index - low)[:, None]
    along = points[low] * (1.0 - frac) + points[low + 1] * frac
    first = joint_paths[0]
    return Trajectory(
        arm=first.arm,
        joint_names=list(first.joint_names),
        times=timed.times.tolist(),
        positions=timed.positions.tolist(),
        velocities=timed.velocities.tolist(),
        accelerations=timed.accelerations.tolist(),
        primitives=[labels[i] for i in np.floor(index).astype(int)],
        wrist_path=[tuple(w) for w in along.tolist()],
        method=method,
    )


def arc_length(wrist: Sequence[Sequence[float]]) -> np.ndarray:
    """Cumulative length of a wrist path [m], shape (n,), from 0."""
    points = np.asarray(wrist, dtype=float)
    steps = np.linalg.norm(np.diff(points, axis=0), axis=1)
    return np.concatenate(([0.0], np.cumsum(steps)))
