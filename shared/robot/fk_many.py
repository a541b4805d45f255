"""Forward kinematics of many postures at once, in numpy.

``ArmModel.fk`` asks pinocchio one posture at a time (about 12 us each);
checking every sample of a long trajectory against NAO's body
(``shared.robot.body``) needs the key points of hundreds of thousands. The
chain here is the same model's: each joint's placement in its parent and
its axis are read from the pinocchio model, and the rotations are composed
for all postures together.
"""

from __future__ import annotations

import numpy as np
import numpy.typing as npt

from shared.robot.arm_model import ArmModel, ArmPoints

#: Axis of each revolute joint type pinocchio builds from the URDF.
AXES = {
    "JointModelRX": 0,
    "JointModelRY": 1,
    "JointModelRZ": 2,
}


def key_points(arm: ArmModel, q: npt.ArrayLike) -> dict[str, np.ndarray]:
    """The arm's key points [m] for postures ``q`` [rad], shape (n, 5).

    Returns:
        ``ArmPoints``' fields (shoulder, elbow, wrist, hand), each shape
        (n, 3), in the torso frame: what ``arm.fk`` gives for each posture.
    """
    postures = np.atleast_2d(np.asarray(q, dtype=float))
    model = arm.model
    count = len(postures)
    rotations = [np.broadcast_to(np.eye(3), (count, 3, 3))]
    positions = [np.zeros((count, 3))]
    for joint in range(1, model.njoints):
        parent = model.parents[joint]
        placement = model.jointPlacements[joint]
        axis = AXES[model.joints[joint].shortname()]
        angle = postures[:, model.joints[joint].idx_q]
        base = rotations[parent] @ placement.rotation
        positions.append(positions[parent] + rotations[parent] @ placement.translation)
        rotations.append(base @ _turns(axis, angle))
    points = {}
    for name in ArmPoints._fields:
        frame = model.frames[arm.frame_ids[name]]
        joint = frame.parentJoint
        offset = rotations[joint] @ frame.placement.translation
        points[name] = positions[joint] + offset
    return points


def _turns(axis: int, angle: np.ndarray) -> np.ndarray:
    """Rotations by ``angle`` [rad], (n,), about coordinate axis ``axis``: (n, 3, 3)."""
    c, s = np.cos(angle), np.sin(angle)
    first, second = (axis + 1) % 3, (axis + 2) % 3  # cyclic: a right-handed turn
    turn = np.zeros((len(angle), 3, 3))
    turn[:, axis, axis] = 1.0
    turn[:, first, first] = c
    turn[:, second, second] = c
    turn[:, first, second] = -s
    turn[:, second, first] = s
    return turn
