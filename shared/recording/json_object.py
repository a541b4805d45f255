"""What a ``json`` channel may hold: a JSON object as RFC 8259 writes one.

MCAP's ``json`` message encoding, and Foxglove with it, reads each message
as JSON in UTF-8. Python's ``json.loads`` is more lenient with bytes: it
guesses UTF-16 and UTF-32, skips a UTF-8 byte order mark, lets encoded
surrogates through, and reads Python's ``NaN`` and ``Infinity``. A payload
it takes may so be unreadable, or read otherwise, elsewhere. The recorder
routes by this stricter test (anything else is kept as a ``RawPayload``),
and ``armplan inspect --validate`` checks the ``json`` channels with it.
"""

from __future__ import annotations

import json

#: The byte order mark, as the first character of decoded text.
BOM = "\ufeff"


def _not_json(constant: str) -> None:
    """``json.loads``' hook for NaN and Infinity, which JSON does not have."""
    raise ValueError(f"{constant} is not JSON")


def json_object_problem(payload: bytes) -> str | None:
    """Why ``payload`` is not a JSON object in UTF-8, in words; ``None`` if it is.

    Args:
        payload: The message's bytes.
    """
    try:
        text = payload.decode("utf-8")  # strict: no surrogates, no UTF-16
    except UnicodeDecodeError:
        return "not UTF-8 text (JSON in UTF-16 or UTF-32, or binary data?)"
    if text.startswith(BOM):
        return "it starts with a byte order mark, which JSON in UTF-8 has not"
    try:
        value = json.loads(text, parse_constant=_not_json)
    except RecursionError:
        return "nested too deeply to read"
    except ValueError as error:
        return f"not JSON ({error})"
    if not isinstance(value, dict):
        return f"a {type(value).__name__}, not a JSON object"
    return None


def is_json_object(payload: bytes) -> bool:
    """Whether ``payload`` is a JSON object in UTF-8 (no NaN, Infinity, BOM)."""
    return json_object_problem(payload) is None
