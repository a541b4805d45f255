"""Forward kinematics of many postures at once, in numpy.

``ArmModel.fk`` asks pinocchio one posture at a time (about 20 us each);
checking every sample of a long trajectory against NAO's body
(``shared.robot.body``) needs the key points of hundreds of thousands. The
chain here is the same model's: each joint's placement in its parent and
its axis are read from the pinocchio model once, and the rotations are
composed for all postures together. One posture or two (the start of a
plan) are quicker asked of pinocchio.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
import numpy.typing as npt
import pinocchio as pin

from shared.robot.arm_model import ArmModel, ArmPoints

#: Axis of each revolute joint type pinocchio builds from the URDF.
AXES = {
    "JointModelRX": 0,
    "JointModelRY": 1,
    "JointModelRZ": 2,
}

#: Fewer postures than this are asked of pinocchio one at a time: composing
#: in numpy has a fixed cost of about four of pinocchio's answers.
ONE_BY_ONE = 3


class Chain(NamedTuple):
    """A model's joints and key frames as numpy arrays, read once.

    Attributes:
        parents: Each joint's parent (joint 0 is the torso), length J.
        rotations: Each joint's placement rotation in its parent, (J, 3, 3).
        translations: Its placement translation [m], (J, 3).
        axes: Its turning axis (0 x, 1 y, 2 z), length J (joint 0: unused).
        angles: Its angle's index in a posture, length J (joint 0: unused).
        frames: For each key point, its joint and offset there [m], (3,).
    """

    parents: tuple[int, ...]
    rotations: np.ndarray
    translations: np.ndarray
    axes: tuple[int, ...]
    angles: tuple[int, ...]
    frames: dict[str, tuple[int, np.ndarray]]


#: The chain of the last model read, per side of ``ArmModel``: (model, chain).
_CHAINS: dict[str, tuple[pin.Model, Chain]] = {}


def chain_of(arm: ArmModel) -> Chain:
    """``arm``'s model as a :class:`Chain`, read once per model object."""
    kept = _CHAINS.get(arm.side.value)
    if kept is not None and kept[0] is arm.model:
        return kept[1]
    model = arm.model
    joints = range(model.njoints)
    placements = [model.jointPlacements[j] for j in joints]
    chain = Chain(
        parents=tuple(int(model.parents[j]) for j in joints),
        rotations=np.array([p.rotation for p in placements]),
        translations=np.array([p.translation for p in placements]),
        axes=(-1, *(AXES[model.joints[j].shortname()] for j in joints[1:])),
        angles=(-1, *(int(model.joints[j].idx_q) for j in joints[1:])),
        frames={
            name: (
                int(model.frames[arm.frame_ids[name]].parentJoint),
                model.frames[arm.frame_ids[name]].placement.translation.copy(),
            )
            for name in ArmPoints._fields
        },
    )
    _CHAINS[arm.side.value] = (model, chain)
    return chain


def key_points(arm: ArmModel, q: npt.ArrayLike) -> dict[str, np.ndarray]:
    """The arm's key points [m] for postures ``q`` [rad], shape (n, 5).

    Returns:
        ``ArmPoints``' fields (shoulder, elbow, wrist, hand), each shape
        (n, 3), in the torso frame: what ``arm.fk`` gives for each posture.
    """
    postures = np.atleast_2d(np.asarray(q, dtype=float))
    count = len(postures)
    if count < ONE_BY_ONE:
        each = [arm.fk(posture) for posture in postures]
        return {
            name: np.array([getattr(points, name) for points in each]).reshape(count, 3)
            for name in ArmPoints._fields
        }
    chain = chain_of(arm)
    rotations = [np.broadcast_to(np.eye(3), (count, 3, 3))]
    positions = [np.zeros((count, 3))]
    for joint in range(1, len(chain.parents)):
        parent = chain.parents[joint]
        base = rotations[parent] @ chain.rotations[joint]
        positions.append(
            positions[parent] + rotations[parent] @ chain.translations[joint]
        )
        rotations.append(
            base @ _turns(chain.axes[joint], postures[:, chain.angles[joint]])
        )
    return {
        name: positions[joint] + rotations[joint] @ offset
        for name, (joint, offset) in chain.frames.items()
    }


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
