"""Which channel a received payload goes to, and what message it is.

The recorder keeps every payload, byte for byte (SPEC: nothing recorded is
lost), and gives each the most specific channel it fits:

1. a JSON object on a registered topic that parses as the topic's message
   class (``shared.bus.topics``), or on a key whose answer the recorder
   asks for itself (``fit/model``, ``services.recorder.model_at_start``),
   that parses as the answer's class: the typed channel, schema named
   after the class (``Trajectory``), its JSON schema from pydantic;
2. any other JSON object (unknown topic, or a payload that does not parse
   as its class): the topic's schemaless channel, schema ``"json"``;
3. anything else (binary, text, JSON that is not an object, JSON not in
   UTF-8 or with a byte order mark, Python's NaN and Infinity, which JSON
   readers such as Foxglove's refuse or read otherwise;
   ``shared.recording.json_object``), and a payload larger than the bus's
   ``max_payload``, unread (no service reads one: parsing a 200 MB
   publication took the recorder to 7 GB): a ``RawPayload`` (base64 and
   the Zenoh encoding) on the topic's ``RawPayload`` channel.

The channel's topic is the sample's full key, e.g. ``armplan/plan/trajectory``.
"""

from __future__ import annotations

from functools import cache
from typing import Any, NamedTuple

from pydantic import ValidationError

from shared.bus.routes import FIT_MODEL
from shared.bus.topics import topic_message
from shared.messages import Message
from shared.recording.json_object import is_json_object
from shared.recording.raw_payload import JSON_SCHEMA, JSON_SCHEMA_NAME, RawPayload


class Incoming(NamedTuple):
    """One sample as the recorder received it.

    Attributes:
        key: The sample's full key, e.g. ``armplan/plan/trajectory``.
        payload: Its bytes.
        encoding: Its Zenoh encoding, e.g. ``"application/json"``.
        log_time: Its Zenoh timestamp if it had one, else ``publish_time``
            [ns since the epoch].
        publish_time: When the recorder received it [ns since the epoch].
    """

    key: str
    payload: bytes
    encoding: str
    log_time: int
    publish_time: int


class Entry(NamedTuple):
    """One message to write.

    Attributes:
        topic: Channel topic (the full key).
        schema_name: The channel's schema name.
        schema: The channel's JSON schema.
        data: The message [UTF-8 JSON bytes].
        message: The parsed message, for typed channels (else ``None``).
    """

    topic: str
    schema_name: str
    schema: dict[str, Any]
    data: bytes
    message: Message | None


#: The answers the recorder asks for and records, by key under the namespace.
#: A replay does not send them: they were answers, not publications.
ASKED: dict[str, type[Message]] = {FIT_MODEL.path: FIT_MODEL.reply}
#: The Zenoh encoding noted on their channels, as a service labels replies.
ASKED_ENCODING = "application/json"


@cache
def typed_schema(cls: type[Message]) -> dict[str, Any]:
    """``cls``'s JSON schema, computed once per class."""
    return cls.json_schema()


def relative_path(key: str, namespace: str) -> str | None:
    """``key`` without ``<namespace>/``; ``None`` if it is outside the namespace."""
    prefix = f"{namespace}/"
    return key[len(prefix) :] if key.startswith(prefix) else None


def _typed(cls: type[Message], payload: bytes) -> Message | None:
    try:
        return cls.model_validate_json(payload)
    except (ValidationError, RecursionError):
        return None


def route(incoming: Incoming, namespace: str, max_payload: int | None = None) -> Entry:
    """The channel and message of one received sample (see the module docstring).

    Args:
        incoming: The sample.
        namespace: The bus namespace, e.g. ``"armplan"``.
        max_payload: Larger payloads are kept raw, unread [bytes]; ``None``:
            every payload is read.
    """
    key, payload = incoming.key, incoming.payload
    too_large = max_payload is not None and len(payload) > max_payload
    if too_large or not is_json_object(payload):
        raw = RawPayload.of(payload, incoming.encoding)
        return Entry(
            key,
            RawPayload.__name__,
            typed_schema(RawPayload),
            raw.to_json().encode(),
            None,
        )
    path = relative_path(key, namespace)
    cls = None if path is None else topic_message(path) or ASKED.get(path)
    message = None if cls is None else _typed(cls, payload)
    if cls is not None and message is not None:
        return Entry(key, cls.__name__, typed_schema(cls), payload, message)
    return Entry(key, JSON_SCHEMA_NAME, JSON_SCHEMA, payload, None)
