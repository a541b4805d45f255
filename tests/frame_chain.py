"""Link poses chained back from a ``foxglove.FrameTransforms`` message's JSON."""

from __future__ import annotations

from typing import Any

import numpy as np


def matrix_from_quaternion(q: Any) -> np.ndarray:
    x, y, z, w = q["x"], q["y"], q["z"], q["w"]
    return np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
            [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
            [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
        ]
    )


def chain_poses(message: dict[str, Any]) -> dict[str, tuple[np.ndarray, np.ndarray]]:
    """Pose (R, p) of every frame in the root frame, from a FrameTransforms JSON."""
    poses = {"torso": (np.eye(3), np.zeros(3))}
    for t in message["transforms"]:
        r_parent, p_parent = poses[t["parent_frame_id"]]
        r = matrix_from_quaternion(t["rotation"])
        v = t["translation"]
        p = np.array([v["x"], v["y"], v["z"]])
        poses[t["child_frame_id"]] = (r_parent @ r, p_parent + r_parent @ p)
    return poses
