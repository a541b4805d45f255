"""Payloads kept byte for byte: not JSON objects, or not of their topic's class.

A recorder never drops what it receives. A payload that is a JSON object is
written as is: on its topic's typed channel if it parses as the topic's
message class, else on the topic's schemaless channel (schema ``"json"``,
any JSON object). Any other payload (binary, text, a JSON array or number)
becomes a :class:`RawPayload`, its bytes in base64 with the Zenoh encoding,
so the file stays JSON throughout and a replay sends the same bytes again.
The Zenoh encoding a JSON object came with is its channel's metadata
(``zenoh_encoding``): a topic gets a channel per schema and encoding.
"""

from __future__ import annotations

import base64
import binascii
from typing import Any

from shared.messages import Message

#: Channel metadata key: the Zenoh encoding of the JSON objects on a channel,
#: e.g. ``"application/json"`` (a ``RawPayload`` carries its own).
ZENOH_ENCODING = "zenoh_encoding"
#: Schema name of the schemaless channels (any JSON object).
JSON_SCHEMA_NAME = "json"
#: Their JSON schema: any JSON object.
JSON_SCHEMA: dict[str, Any] = {
    "type": "object",
    "description": "any JSON object (no armplan message class for this key, "
    "or the payload did not parse as its class)",
}


class RawPayload(Message):
    """A payload that is not a JSON object (or one the recorder left unread).

    Attributes:
        encoding: The Zenoh encoding it came with, e.g. ``"zenoh/bytes"``.
        base64: Its bytes, base64-encoded (RFC 4648, standard alphabet).
    """

    encoding: str
    base64: str

    @classmethod
    def of(cls, payload: bytes, encoding: str) -> RawPayload:
        """Wrap ``payload`` [bytes] received with ``encoding``."""
        return cls(encoding=encoding, base64=base64.b64encode(payload).decode())

    def payload(self) -> bytes:
        """The original bytes.

        Raises:
            ValueError: if ``base64`` is not valid base64.
        """
        try:
            return base64.b64decode(self.base64, validate=True)
        except binascii.Error as exc:
            raise ValueError(f"RawPayload.base64 is not base64: {exc}") from None
