"""The arm's link poses, link by link, from the robot file's kinematics.

One transform per joint of the robot description, parent link to child link,
exactly as a URDF viewer chains them: ``torso -> RShoulder -> RBicep ->
RElbow -> RForeArm -> r_wrist -> r_gripper`` (right arm; ``L...``/``l_...``
for the left). Each is the joint's origin followed by its rotation by the
joint angle, read from pinocchio (``data.liMi``) after forward kinematics of
the model ``shared.robot`` loads from the URDF, so chaining them gives the
arm's forward kinematics (``ArmModel.fk``). The gripper's transform is its
fixed placement on the wrist (the hand's open fraction does not move it).
"""

from __future__ import annotations

from functools import cache
from typing import NamedTuple

import numpy as np
import numpy.typing as npt
import pinocchio as pin

from shared.robot import ArmModel, Side, load_arm

#: The robot description's root link (NAOqi's FRAME_TORSO).
ROOT_LINK = "torso"


class LinkTransform(NamedTuple):
    """The pose of one link in its parent link.

    Attributes:
        parent: Parent link name, e.g. ``"torso"``.
        child: Child link name, e.g. ``"RShoulder"``.
        translation: Child origin in the parent frame [m], shape (3,).
        rotation: Child orientation as a unit quaternion (x, y, z, w), shape (4,).
    """

    parent: str
    child: str
    translation: np.ndarray
    rotation: np.ndarray


class _Chain(NamedTuple):
    """The link names and frame ids of one arm's chain in its pinocchio model."""

    links: tuple[str, ...]
    hand_frame: int


def _body_of_joint(model: pin.Model, joint: int) -> str:
    """The link (BODY frame) that joint ``joint`` moves, at the joint's origin."""
    for frame in model.frames:
        if (
            frame.type == pin.FrameType.BODY
            and frame.parentJoint == joint
            and frame.placement.isIdentity()
        ):
            return str(frame.name)
    raise LookupError(f"no link at the origin of joint {model.names[joint]}")


@cache
def _chain(side: Side) -> _Chain:
    arm = load_arm(side)
    model = arm.model
    links = tuple(_body_of_joint(model, j) for j in range(model.njoints))
    gripper = ("r" if side is Side.RIGHT else "l") + "_gripper"
    return _Chain((*links, gripper), model.getFrameId(gripper))


def arm_links(side: Side | str) -> tuple[str, ...]:
    """The arm's link names, root first, e.g. ``("torso", "RShoulder", ...)``."""
    return _chain(Side.parse(side)).links


def quaternion_from_matrix(rotation: npt.ArrayLike) -> np.ndarray:
    """Unit quaternion (x, y, z, w) with w >= 0 of a rotation matrix (3, 3)."""
    q = pin.Quaternion(np.asarray(rotation, dtype=float)).coeffs().copy()
    return -q if q[3] < 0 else q


class LinkPoses(NamedTuple):
    """Every link's pose in its parent link, for many postures, as arrays.

    Attributes:
        parents: Parent link names, root first, shape (6,).
        children: Child link names, shape (6,).
        translations: Child origins in their parents [m], shape (n, 6, 3).
        rotations: Child orientations as unit quaternions (x, y, z, w) with
            w >= 0, shape (n, 6, 4).
    """

    parents: tuple[str, ...]
    children: tuple[str, ...]
    translations: np.ndarray
    rotations: np.ndarray


def link_poses(arm: ArmModel, angles: npt.ArrayLike) -> LinkPoses:
    """Every link's pose in its parent for each posture of ``angles``.

    Pinocchio's forward kinematics, posture by posture, read straight into
    arrays (42 floats a posture, no object per posture), so the numbers are
    :func:`link_transforms`' to the bit: 41 000 postures take 14 MB and
    0.9 s.

    Args:
        arm: The arm (its pinocchio data buffer is used; not thread-safe).
        angles: Joint angles [rad], shape (n, 5), in the paper's order.

    Returns:
        Six transforms per posture, root first: five joints, then the gripper.
    """
    chain = _chain(arm.side)
    q = np.asarray(angles, dtype=float)
    n, joints = len(q), arm.model.njoints - 1
    translations = np.empty((n, joints + 1, 3))
    rotations = np.empty((n, joints + 1, 4))
    hand = arm.model.frames[chain.hand_frame].placement
    translations[:, joints] = hand.translation
    rotations[:, joints] = quaternion_from_matrix(hand.rotation)
    for k in range(n):
        pin.forwardKinematics(arm.model, arm.data, q[k])
        for joint in range(1, joints + 1):
            pose = arm.data.liMi[joint]
            translations[k, joint - 1] = pose.translation
            rotations[k, joint - 1] = quaternion_from_matrix(pose.rotation)
    return LinkPoses(chain.links[:-1], chain.links[1:], translations, rotations)


def link_transforms(arm: ArmModel, q: npt.ArrayLike) -> list[LinkTransform]:
    """Every link's pose in its parent for joint angles ``q``.

    Args:
        arm: The arm (its pinocchio data buffer is used; not thread-safe).
        q: Joint angles [rad], shape (5,), in the paper's order.

    Returns:
        Six transforms, root first: five joints, then the gripper.
    """
    poses = link_poses(arm, np.asarray(q, dtype=float)[np.newaxis])
    return [
        LinkTransform(parent, child, translation, rotation)
        for parent, child, translation, rotation in zip(
            poses.parents,
            poses.children,
            poses.translations[0],
            poses.rotations[0],
            strict=True,
        )
    ]
