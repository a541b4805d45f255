"""Foxglove-ready channels derived from the messages a session records.

| channel | schema | from |
|---|---|---|
| ``/robot_description`` | ``RobotDescription`` | the project's URDF, once per file |
| ``/tf/planned`` | ``foxglove.FrameTransforms`` | each ``Trajectory``, one per sample |
| ``/tf/executed`` | ``foxglove.FrameTransforms`` | each measured ``JointState`` |
| ``/decision`` | ``PrimitiveSample`` | each ``Decision``, one per path point |
| ``/primitive/planned`` | ``PrimitiveSample`` | each ``Trajectory``'s labels |

Derived channels start with ``/``, which no Zenoh key does, so a replay
never republishes them.
"""

from __future__ import annotations

from typing import Any, NamedTuple

from shared.messages import Decision, Message, Trajectory
from shared.messages.frames import JointState
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
from shared.recording.foxglove.transforms import (
    Stamped,
    executed_transforms,
    planned_transforms,
    side_of_state,
)
from shared.robot import ArmModel, Side, load_arm

PLANNED_TF_TOPIC = "/tf/planned"
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
    """

    def __init__(self, planned_prefix: str = "", executed_prefix: str = "executed/"):
        self.planned_prefix = planned_prefix
        self.executed_prefix = executed_prefix
        self._arms: dict[Side, ArmModel] = {}

    def _arm(self, side: Side) -> ArmModel:
        if side not in self._arms:
            self._arms[side] = load_arm(side)
        return self._arms[side]

    def derive(self, message: Message, log_time: int) -> list[Derived]:
        """The derived messages of ``message`` received at ``log_time`` [ns].

        Raises:
            KeyError: a trajectory or state lacks one of its arm's joints.
        """
        if isinstance(message, Trajectory):
            return self._trajectory(message, log_time)
        if isinstance(message, JointState):
            return self._state(message, log_time)
        if isinstance(message, Decision):
            return _samples(DECISION_TOPIC, decision_samples(message, log_time))
        return []

    def _trajectory(self, trajectory: Trajectory, log_time: int) -> list[Derived]:
        arm = self._arm(Side.parse(trajectory.arm))
        poses = planned_transforms(arm, trajectory, log_time, self.planned_prefix)
        labels = trajectory_samples(trajectory, log_time)
        return _transforms(PLANNED_TF_TOPIC, poses) + _samples(
            PLANNED_PRIMITIVE_TOPIC, labels
        )

    def _state(self, state: JointState, log_time: int) -> list[Derived]:
        side = side_of_state(state)
        if side is None:
            return []
        pose = executed_transforms(
            self._arm(side), state, log_time, self.executed_prefix
        )
        return _transforms(EXECUTED_TF_TOPIC, [pose])


def _transforms(topic: str, stamped: list[Stamped]) -> list[Derived]:
    schema = frame_transforms_schema()
    return [
        Derived(
            topic,
            FRAME_TRANSFORMS_SCHEMA_NAME,
            schema,
            s.message.to_json().encode(),
            s.log_time,
        )
        for s in stamped
    ]


def _samples(topic: str, samples: list[tuple[int, PrimitiveSample]]) -> list[Derived]:
    schema = PrimitiveSample.json_schema()
    return [
        Derived(topic, PrimitiveSample.__name__, schema, s.to_json().encode(), t)
        for t, s in samples
    ]
