"""Foxglove-ready channels derived from the messages a session records.

| channel | schema | from |
|---|---|---|
| ``/robot_description`` | ``RobotDescription`` | the project's URDF, once per file |
| ``/tf/planned`` | ``foxglove.FrameTransforms`` | each ``Trajectory``, one per sample |
| ``/tf/commanded`` | ``foxglove.FrameTransforms`` | each ``CommandFrames`` frame |
| ``/tf/executed`` | ``foxglove.FrameTransforms`` | each measured ``JointState`` |
| ``/decision`` | ``PrimitiveSample`` | each ``Decision``, one per path point |
| ``/primitive/planned`` | ``PrimitiveSample`` | each ``Trajectory``'s labels |

Each ``PrimitiveSample`` names its arm (``arm``, ``"right"`` or ``"left"``).

Derived channels start with ``/``, which no Zenoh key does, so a replay
never republishes them. A decision point is placed when the trajectory
passes it (:func:`decision_stamps`).
"""

from __future__ import annotations

from collections.abc import Iterator, Sequence
from itertools import chain
from typing import Any, NamedTuple

from shared.messages import Decision, Message, Trajectory
from shared.messages.frames import CommandFrames, JointState
from shared.recording.foxglove.link_poses import link_poses
from shared.recording.foxglove.primitive import (
    PrimitiveSample,
    decision_samples,
    trajectory_samples,
)
from shared.recording.foxglove.robot_description import (
    ROBOT_DESCRIPTION_TOPIC,
    RobotDescription,
    robot_description,
)
from shared.recording.foxglove.schemas import (
    FRAME_TRANSFORMS_SCHEMA_NAME,
    frame_transforms_schema,
)
from shared.recording.foxglove.stamps import check_stamp, sample_stamps
from shared.recording.foxglove.transforms import (
    executed_transforms,
    frames_angles,
    side_of_state,
    trajectory_angles,
    transforms_json,
)
from shared.robot import ArmModel, Side, load_arm

PLANNED_TF_TOPIC = "/tf/planned"
COMMANDED_TF_TOPIC = "/tf/commanded"
EXECUTED_TF_TOPIC = "/tf/executed"
DECISION_TOPIC = "/decision"
PLANNED_PRIMITIVE_TOPIC = "/primitive/planned"


class Derived(NamedTuple):
    """One message of a derived channel, ready to write.

    Attributes:
        topic: Channel topic, e.g. ``"/tf/planned"``.
        schema_name: Schema name, e.g. ``"foxglove.FrameTransforms"``.
        schema: The JSON schema.
        data: The message's JSON [UTF-8 bytes].
        log_time: When it applies [ns since the epoch].
    """

    topic: str
    schema_name: str
    schema: dict[str, Any]
    data: bytes
    log_time: int


def description_message(log_time: int) -> Derived:
    """The ``/robot_description`` message stamped ``log_time`` [ns]."""
    return Derived(
        ROBOT_DESCRIPTION_TOPIC,
        RobotDescription.__name__,
        RobotDescription.json_schema(),
        robot_description().to_json().encode(),
        log_time,
    )


class FoxgloveChannels:
    """Turns recorded messages into the derived channels' messages.

    Not thread-safe (one arm model per side, reused).

    Args:
        planned_prefix: Frame prefix of planned motion ("" moves the URDF).
        executed_prefix: Frame prefix of executed motion.
        commanded_prefix: Frame prefix of the frames the bridge commands.
    """

    def __init__(
        self,
        planned_prefix: str = "",
        executed_prefix: str = "executed/",
        commanded_prefix: str = "commanded/",
    ):
        self.planned_prefix = planned_prefix
        self.executed_prefix = executed_prefix
        self.commanded_prefix = commanded_prefix
        self._arms: dict[Side, ArmModel] = {}

    def _arm(self, side: Side) -> ArmModel:
        if side not in self._arms:
            self._arms[side] = load_arm(side)
        return self._arms[side]

    @staticmethod
    def derives(message: Message) -> bool:
        """Whether ``message`` has derived messages (of a kind that has them)."""
        return isinstance(message, (Trajectory, CommandFrames, JointState, Decision))

    def derive(self, message: Message, log_time: int) -> Iterator[Derived]:
        """The derived messages of ``message`` received at ``log_time`` [ns].

        Every check is made here, at the call: a message either raises now
        or gives all of its derived messages. They are made one at a time as
        they are taken (a trajectory of 40 000 samples gives 80 000), from
        its link poses computed at the call: writing each as it comes keeps
        one message in memory, not all of them.

        Raises:
            KeyError: a trajectory or state lacks one of its arm's joints.
            ValueError: a derived message's time passes MCAP's range.
        """
        if isinstance(message, Trajectory):
            return self._trajectory(message, log_time)
        if isinstance(message, CommandFrames):
            return self._frames(message, log_time)
        if isinstance(message, JointState):
            return self._state(message, log_time)
        if isinstance(message, Decision):
            stamps = decision_stamps(message, log_time)
            return _samples(DECISION_TOPIC, stamps, decision_samples(message))
        return iter(())

    def _trajectory(self, trajectory: Trajectory, log_time: int) -> Iterator[Derived]:
        arm = self._arm(Side.parse(trajectory.arm))
        angles = trajectory_angles(trajectory)
        stamps = sample_stamps(trajectory.times, log_time)
        poses = transforms_json(link_poses(arm, angles), stamps, self.planned_prefix)
        labels = trajectory_samples(trajectory)
        return chain(
            _transforms(PLANNED_TF_TOPIC, stamps, poses),
            _samples(PLANNED_PRIMITIVE_TOPIC, stamps, labels),
        )

    def _frames(self, frames: CommandFrames, log_time: int) -> Iterator[Derived]:
        """The commanded arm: frame 0 (the start) at arrival, frame k later by its time.

        The bridge publishes the frames as the movement starts.
        """
        angles = frames_angles(frames)
        stamps = sample_stamps([0.0, *frames.times], log_time)
        arm = self._arm(frames.arm)
        poses = transforms_json(link_poses(arm, angles), stamps, self.commanded_prefix)
        return _transforms(COMMANDED_TF_TOPIC, stamps, poses)

    def _state(self, state: JointState, log_time: int) -> Iterator[Derived]:
        side = side_of_state(state)
        if side is None:
            return iter(())
        stamp = check_stamp(log_time, "the state")
        pose = executed_transforms(self._arm(side), state, stamp, self.executed_prefix)
        return _transforms(EXECUTED_TF_TOPIC, [stamp], iter([pose]))


def decision_stamps(decision: Decision, log_time: int) -> list[int]:
    """When each point of ``decision``, received at ``log_time`` [ns], applies [ns].

    With ``trajectory_times`` (the planner's decisions, published right
    after their trajectory): the arrival plus when the trajectory passes
    the point, so the reaches of a task follow each other as the
    trajectory's samples do. Without (recorded before the field existed, or
    from another publisher): the arrival plus the point's own time from the
    first, each reach's from 0, as then.

    Raises:
        ValueError: a stamp passes MCAP's range.
    """
    if decision.trajectory_times is None:
        return sample_stamps(decision.times, log_time)
    return sample_stamps(decision.trajectory_times, log_time, origin=0.0)


def _transforms(
    topic: str, stamps: Sequence[int], messages: Iterator[bytes]
) -> Iterator[Derived]:
    """``foxglove.FrameTransforms`` on ``topic``, one per stamp [ns]."""
    schema = frame_transforms_schema()
    for stamp, data in zip(stamps, messages, strict=True):
        yield Derived(topic, FRAME_TRANSFORMS_SCHEMA_NAME, schema, data, stamp)


def _samples(
    topic: str, stamps: Sequence[int], samples: Iterator[PrimitiveSample]
) -> Iterator[Derived]:
    """``PrimitiveSample`` messages on ``topic``, one per stamp [ns]."""
    schema = PrimitiveSample.json_schema()
    for stamp, sample in zip(stamps, samples, strict=True):
        yield Derived(
            topic, PrimitiveSample.__name__, schema, sample.to_json().encode(), stamp
        )
