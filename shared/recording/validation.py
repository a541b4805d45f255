"""Check recorded messages against their channels' schemas.

Each channel's schema is named after a pydantic model (``Trajectory``,
``PrimitiveSample``, ``foxglove.FrameTransforms``, ...); a message is valid
if that model parses it. ``"json"`` (schemaless) channels accept any JSON
object in UTF-8 (``shared.recording.json_object``). This stands in for a
JSON-schema validator: the models are where the schemas come from
(Foxglove's own are mirrored field for field in
``shared.recording.foxglove.schemas``).
"""

from __future__ import annotations

from functools import cache

from pydantic import BaseModel, ValidationError

from shared.bus.topics import TOPICS
from shared.messages.base import describe_validation_error
from shared.messages.demo import DemoSample, DemoSubject
from shared.printable import printable
from shared.recording.foxglove import (
    FRAME_TRANSFORMS_SCHEMA_NAME,
    FrameTransforms,
    PrimitiveSample,
    RobotDescription,
)
from shared.recording.json_object import json_object_problem
from shared.recording.raw_payload import JSON_SCHEMA_NAME, RawPayload
from shared.recording.reader import Record


@cache
def schema_models() -> dict[str, type[BaseModel]]:
    """The model behind each schema name armplan writes.

    The recorder's, and the demonstration files' (``shared.demos.demo_file``).
    """
    models: dict[str, type[BaseModel]] = {
        m.__name__: m
        for m in (
            PrimitiveSample,
            RobotDescription,
            RawPayload,
            DemoSubject,
            DemoSample,
        )
    }
    models[FRAME_TRANSFORMS_SCHEMA_NAME] = FrameTransforms
    for topic in TOPICS:
        if topic.message is not None:
            models[topic.message.__name__] = topic.message
    return models


def check_record(record: Record) -> str | None:
    """What is wrong with ``record`` against its channel's schema (``None``: valid).

    A message the reader could not read (``Record.unread``: its channel is
    not JSON, or it is not JSON) matches no schema. The answer is made
    printable: its topic, and the field names it quotes, come from the file.
    """
    problem = _problem(record)
    return None if problem is None else printable(problem)


def _problem(record: Record) -> str | None:
    """``check_record``'s answer, as the file gives its names."""
    if record.unread:
        return f"{record.topic}: {record.unread}"
    if record.schema == JSON_SCHEMA_NAME:
        if record.raw:  # as written: the reader's data may come from UTF-16
            problem = json_object_problem(record.raw)
            return None if problem is None else f"{record.topic}: {problem}"
        if isinstance(record.data, dict):
            return None
        return f"{record.topic}: a {type(record.data).__name__}, not a JSON object"
    model = schema_models().get(record.schema)
    if model is None:
        return f"{record.topic}: no armplan model for schema {record.schema!r}"
    try:
        if record.raw:
            model.model_validate_json(record.raw)
        else:
            model.model_validate(record.data)
    except ValidationError as exc:
        return f"{record.topic} ({record.schema}): {describe_validation_error(exc)[1]}"
    return None
