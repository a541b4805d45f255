"""Planned and executed arm motion as timed ``foxglove.FrameTransforms``.

Planned motion comes from a trajectory: one message per sample, stamped at
the trajectory's arrival plus the sample's time from its first sample (the
moment the plan says the arm is there). Executed motion comes from each
measured joint state the bridge publishes, stamped when it arrived.

Frame names are the robot description's link names, optionally prefixed.
Without a prefix the transforms move the URDF that ``/robot_description``
loads into Foxglove's 3D panel (they replace the URDF's joint-origin
transforms, which Foxglove stamps at time 0); with a prefix (e.g.
``"executed/"``) a second arm appears beside it as a tree of axes. The root
link ``torso`` is never prefixed, so both hang from the same torso.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import NamedTuple

import numpy as np
import numpy.typing as npt

from shared.messages import Trajectory
from shared.messages.frames import JointState
from shared.recording.foxglove.link_poses import (
    ROOT_LINK,
    LinkTransform,
    link_transforms,
)
from shared.recording.foxglove.schemas import (
    FrameTransform,
    FrameTransforms,
    Quaternion,
    Time,
    Vector3,
)
from shared.robot import JOINTS, ArmModel, Side

_NS_PER_S = 1_000_000_000


class Stamped(NamedTuple):
    """A derived message and the time it belongs to.

    Attributes:
        log_time: When the message applies [ns since the epoch].
        message: The message.
    """

    log_time: int
    message: FrameTransforms


def _frame(name: str, prefix: str) -> str:
    return name if name == ROOT_LINK else prefix + name


def frame_transforms(
    arm: ArmModel, q: npt.ArrayLike, stamp: int, prefix: str = ""
) -> FrameTransforms:
    """The arm's link transforms for angles ``q`` as one Foxglove message.

    Args:
        arm: The arm model (its data buffer is used).
        q: Joint angles [rad], shape (5,), paper order.
        stamp: The transforms' timestamp [ns since the epoch].
        prefix: Prepended to every frame name but the root ``torso``.
    """
    time = Time.from_ns(stamp)
    return FrameTransforms(
        transforms=[_transform(t, time, prefix) for t in link_transforms(arm, q)]
    )


def _transform(link: LinkTransform, time: Time, prefix: str) -> FrameTransform:
    """One link's transform as a Foxglove ``FrameTransform`` stamped ``time``."""
    x, y, z = (float(v) for v in link.translation)
    qx, qy, qz, qw = (float(v) for v in link.rotation)
    return FrameTransform(
        timestamp=time,
        parent_frame_id=_frame(link.parent, prefix),
        child_frame_id=_frame(link.child, prefix),
        translation=Vector3(x=x, y=y, z=z),
        rotation=Quaternion(x=qx, y=qy, z=qz, w=qw),
    )


def arm_angles(side: Side, names: Sequence[str], values: Sequence[float]) -> np.ndarray:
    """The five arm angles [rad] in paper order from named values.

    Raises:
        KeyError: naming the arm joint missing from ``names``.
    """
    by_name = dict(zip(names, values, strict=True))
    return np.array([float(by_name[side.prefix + joint]) for joint in JOINTS])


def planned_transforms(
    arm: ArmModel, trajectory: Trajectory, start: int, prefix: str = ""
) -> list[Stamped]:
    """One transforms message per trajectory sample.

    Args:
        arm: The model of ``trajectory.arm``.
        trajectory: The planned trajectory.
        start: When its first sample applies [ns since the epoch].
        prefix: Frame name prefix (see the module docstring).

    Raises:
        KeyError: if the trajectory lacks one of the arm's five joints.
    """
    side = Side.parse(trajectory.arm)
    t0 = trajectory.times[0]
    out = []
    for t, row in zip(trajectory.times, trajectory.positions, strict=True):
        stamp = start + round((t - t0) * _NS_PER_S)
        q = arm_angles(side, trajectory.joint_names, row)
        out.append(Stamped(stamp, frame_transforms(arm, q, stamp, prefix)))
    return out


def executed_transforms(
    arm: ArmModel, state: JointState, stamp: int, prefix: str = "executed/"
) -> Stamped:
    """The transforms of one measured joint state.

    Args:
        arm: The model of the state's arm (see :func:`side_of_state`).
        state: Measured angles, named.
        stamp: When they were measured (or received) [ns since the epoch].
        prefix: Frame name prefix.

    Raises:
        KeyError: if the state lacks one of the arm's five joints.
    """
    q = arm_angles(arm.side, state.joint_names, state.positions)
    return Stamped(stamp, frame_transforms(arm, q, stamp, prefix))


def side_of_state(state: JointState) -> Side | None:
    """The arm whose five joints ``state`` names (``None`` if neither's)."""
    names = set(state.joint_names)
    for side in Side:
        if set(side.joint_names) <= names:
            return side
    return None
