"""Planned and executed arm motion as timed ``foxglove.FrameTransforms``.

Planned motion comes from a trajectory: one message per sample, stamped at
the trajectory's arrival plus the sample's time from its first sample (the
moment the plan says the arm is there). Commanded motion comes from the
frames the bridge publishes as it starts a movement (after its approach to
the start posture): one message per frame, stamped at their arrival plus
the frame's time. Executed motion comes from each measured joint state the
bridge publishes, stamped when it arrived. Commanded and executed motion
are on the robot's clock, so they overlay during playback; planned motion
runs earlier, by the time between the plan and the play.

Frame names are the robot description's link names, optionally prefixed.
Without a prefix the transforms move the URDF that ``/robot_description``
loads into Foxglove's 3D panel (they replace the URDF's joint-origin
transforms, which Foxglove stamps at time 0); with a prefix (e.g.
``"executed/"``) a second arm appears beside it as a tree of axes. The root
link ``torso`` is never prefixed, so both hang from the same torso.

A trajectory's messages are made one at a time, as they are written: its
link poses are computed first, into arrays (:func:`link_poses`), and each
message's JSON is then made from one row of them, byte for byte the JSON of
the pydantic model :func:`frame_transforms` builds, without building it.
For 41 000 samples the poses take 14 MB; the models took about 700 MB.
"""

from __future__ import annotations

from collections.abc import Iterator, Sequence

import numpy as np
import numpy.typing as npt
from pydantic_core import to_json

from shared.messages import Trajectory
from shared.messages.frames import CommandFrames, JointState
from shared.recording.foxglove.link_poses import (
    ROOT_LINK,
    LinkPoses,
    LinkTransform,
    link_poses,
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


def trajectory_angles(trajectory: Trajectory) -> np.ndarray:
    """The five arm angles [rad] of every sample, paper order, shape (n, 5).

    Raises:
        KeyError: naming the arm joint missing from ``trajectory.joint_names``.
    """
    side = Side.parse(trajectory.arm)
    column = {name: i for i, name in enumerate(trajectory.joint_names)}
    columns = [column[side.prefix + joint] for joint in JOINTS]
    return np.asarray(trajectory.positions, dtype=float)[:, columns]


def frames_angles(frames: CommandFrames) -> np.ndarray:
    """The five arm angles [rad] of frame 0 (the start) and later frames, (m + 1, 5).

    Paper order.

    Raises:
        KeyError: naming the arm joint missing from ``frames.joint_names``.
    """
    rows = np.vstack([frames.start, frames.positions])
    column = {name: i for i, name in enumerate(frames.joint_names)}
    return rows[:, [column[frames.arm.prefix + joint] for joint in JOINTS]]


def transforms_json(
    poses: LinkPoses, stamps: Sequence[int], prefix: str = ""
) -> Iterator[bytes]:
    """Each posture's ``foxglove.FrameTransforms`` JSON, one at a time.

    The bytes of ``frame_transforms(...).to_json()`` (the same serializer,
    pydantic's, on the same numbers) without a model per posture.

    Args:
        poses: The link poses of n postures.
        stamps: Each posture's timestamp [ns since the epoch], shape (n,).
        prefix: Prepended to every frame name but the root ``torso``.
    """
    frames = [
        (_frame(parent, prefix), _frame(child, prefix))
        for parent, child in zip(poses.parents, poses.children, strict=True)
    ]
    for stamp, translations, rotations in zip(
        stamps, poses.translations, poses.rotations, strict=True
    ):
        sec, nsec = divmod(stamp, _NS_PER_S)
        time = {"sec": sec, "nsec": nsec}
        yield to_json(
            {
                "transforms": [
                    {
                        "timestamp": time,
                        "parent_frame_id": parent,
                        "child_frame_id": child,
                        "translation": {"x": x, "y": y, "z": z},
                        "rotation": {"x": qx, "y": qy, "z": qz, "w": qw},
                    }
                    for (parent, child), (x, y, z), (qx, qy, qz, qw) in zip(
                        frames, translations.tolist(), rotations.tolist(), strict=True
                    )
                ]
            }
        )


def executed_transforms(
    arm: ArmModel, state: JointState, stamp: int, prefix: str = "executed/"
) -> bytes:
    """The transforms of one measured joint state.

    Args:
        arm: The model of the state's arm (see :func:`side_of_state`).
        state: Measured angles, named.
        stamp: When they were measured (or received) [ns since the epoch].
        prefix: Frame name prefix.

    Returns:
        Its ``foxglove.FrameTransforms`` [UTF-8 JSON bytes].

    Raises:
        KeyError: if the state lacks one of the arm's five joints.
    """
    q = arm_angles(arm.side, state.joint_names, state.positions)
    return next(transforms_json(link_poses(arm, q[np.newaxis]), [stamp], prefix))


def side_of_state(state: JointState) -> Side | None:
    """The arm whose five joints ``state`` names (``None`` if neither's)."""
    names = set(state.joint_names)
    for side in Side:
        if set(side.joint_names) <= names:
            return side
    return None
