"""Foxglove's ``foxglove.FrameTransforms`` message: JSON schema and pydantic models.

The JSON schema is the one Foxglove documents for JSON-encoded channels
(``schemas/jsonschema/FrameTransforms.json`` of github.com/foxglove/foxglove-sdk,
the same in github.com/foxglove/schemas; field reference at
https://docs.foxglove.dev/docs/sdk/schemas/frame-transforms): an object with
``transforms``, an array of ``foxglove.FrameTransform`` (``timestamp`` as
``{sec, nsec}``, ``parent_frame_id``, ``child_frame_id``, ``translation`` a
``foxglove.Vector3`` [m], ``rotation`` a ``foxglove.Quaternion`` x, y, z, w).
Foxglove recognises the channel by the schema *name* ``foxglove.FrameTransforms``.

The pydantic models mirror that schema field for field; they build the
messages and validate recorded ones (``jsonschema`` is not a dependency).
"""

from __future__ import annotations

from typing import Any

from pydantic import BaseModel, ConfigDict, Field

#: The schema name Foxglove's 3D panel recognises.
FRAME_TRANSFORMS_SCHEMA_NAME = "foxglove.FrameTransforms"
_NS_PER_S = 1_000_000_000


class FoxgloveMessage(BaseModel):
    """Base of the Foxglove models: frozen, no unknown fields, finite numbers."""

    model_config = ConfigDict(frozen=True, extra="forbid", allow_inf_nan=False)


class Time(FoxgloveMessage):
    """A time as Foxglove writes it: whole seconds and nanoseconds."""

    sec: int = Field(ge=0)
    nsec: int = Field(ge=0, le=_NS_PER_S - 1)

    @classmethod
    def from_ns(cls, ns: int) -> Time:
        """The time ``ns`` [ns since the epoch]."""
        return cls(sec=ns // _NS_PER_S, nsec=ns % _NS_PER_S)

    @property
    def ns(self) -> int:
        """The time in [ns since the epoch]."""
        return self.sec * _NS_PER_S + self.nsec


class Vector3(FoxgloveMessage):
    """``foxglove.Vector3``: a translation [m]."""

    x: float
    y: float
    z: float


class Quaternion(FoxgloveMessage):
    """``foxglove.Quaternion``: a rotation, scalar part ``w`` last."""

    x: float
    y: float
    z: float
    w: float


class FrameTransform(FoxgloveMessage):
    """``foxglove.FrameTransform``: the pose of ``child_frame_id`` in its parent."""

    timestamp: Time
    parent_frame_id: str
    child_frame_id: str
    translation: Vector3
    rotation: Quaternion


class FrameTransforms(FoxgloveMessage):
    """``foxglove.FrameTransforms``: several transforms in one message."""

    transforms: list[FrameTransform]

    def to_json(self) -> str:
        """The message as compact JSON."""
        return self.model_dump_json()


def _number(description: str) -> dict[str, Any]:
    return {"type": "number", "description": description}


def _time_schema(description: str) -> dict[str, Any]:
    return {
        "type": "object",
        "title": "time",
        "properties": {
            "sec": {"type": "integer", "minimum": 0},
            "nsec": {"type": "integer", "minimum": 0, "maximum": _NS_PER_S - 1},
        },
        "description": description,
    }


def _vector3_schema(description: str) -> dict[str, Any]:
    return {
        "title": "foxglove.Vector3",
        "description": description,
        "type": "object",
        "properties": {
            axis: _number(f"{axis} coordinate length") for axis in ("x", "y", "z")
        },
    }


def _quaternion_schema(description: str) -> dict[str, Any]:
    return {
        "title": "foxglove.Quaternion",
        "description": description,
        "type": "object",
        "properties": {part: _number(f"{part} value") for part in "xyzw"},
    }


def frame_transform_schema() -> dict[str, Any]:
    """Foxglove's JSON schema of one ``foxglove.FrameTransform``."""
    return {
        "title": "foxglove.FrameTransform",
        "description": "A transform between two reference frames in 3D space",
        "type": "object",
        "properties": {
            "timestamp": _time_schema("Timestamp of transform"),
            "parent_frame_id": {
                "type": "string",
                "description": "Name of the parent frame",
            },
            "child_frame_id": {
                "type": "string",
                "description": "Name of the child frame",
            },
            "translation": _vector3_schema("Translation component of the transform"),
            "rotation": _quaternion_schema("Rotation component of the transform"),
        },
    }


def frame_transforms_schema() -> dict[str, Any]:
    """Foxglove's JSON schema of ``foxglove.FrameTransforms``."""
    return {
        "title": FRAME_TRANSFORMS_SCHEMA_NAME,
        "description": "An array of FrameTransform messages",
        "type": "object",
        "properties": {
            "transforms": {
                "type": "array",
                "items": frame_transform_schema(),
                "description": "Array of transforms",
            }
        },
    }
