"""Foxglove-ready channels: the arm's link poses, the URDF, the primitive per moment.

See ``docs/recording.md`` for how to view a recording in Foxglove.
"""

from shared.recording.foxglove.derive import (
    COMMANDED_TF_TOPIC,
    DECISION_TOPIC,
    EXECUTED_TF_TOPIC,
    PLANNED_PRIMITIVE_TOPIC,
    PLANNED_TF_TOPIC,
    Derived,
    FoxgloveChannels,
    description_message,
)
from shared.recording.foxglove.link_poses import (
    LinkTransform,
    arm_links,
    link_transforms,
)
from shared.recording.foxglove.primitive import PRIMITIVE_NAMES, PrimitiveSample
from shared.recording.foxglove.robot_description import (
    ROBOT_DESCRIPTION_TOPIC,
    RobotDescription,
)
from shared.recording.foxglove.schemas import (
    FRAME_TRANSFORMS_SCHEMA_NAME,
    FrameTransform,
    FrameTransforms,
    frame_transforms_schema,
)

__all__ = [
    "COMMANDED_TF_TOPIC",
    "DECISION_TOPIC",
    "EXECUTED_TF_TOPIC",
    "FRAME_TRANSFORMS_SCHEMA_NAME",
    "PLANNED_PRIMITIVE_TOPIC",
    "PLANNED_TF_TOPIC",
    "PRIMITIVE_NAMES",
    "ROBOT_DESCRIPTION_TOPIC",
    "Derived",
    "FoxgloveChannels",
    "FrameTransform",
    "FrameTransforms",
    "LinkTransform",
    "PrimitiveSample",
    "RobotDescription",
    "arm_links",
    "description_message",
    "frame_transforms_schema",
    "link_transforms",
]
