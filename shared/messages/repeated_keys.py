"""A hand-written JSON file holds each key once per object.

JSON parsers, pydantic's included, keep the last of a repeated key and drop
the others without a word: a task file with ``"targets"`` written twice (one
list pasted under the other) was planned with the second list alone, and a
target with two ``"dwell"`` values rested the last one. A robot then moves
other than the file reads. :func:`check_keys_once` refuses such a file,
naming the key; the task readers call it on the files a person edits
(``armplan plan --task``, ``armplan demo --task``), not on the bus's
messages, written by programs.
"""

from __future__ import annotations

import json
from typing import Any

from shared.errors import InvalidInputError


def check_keys_once(text: bytes | str, what: str) -> None:
    """Refuse ``text`` if an object in it holds a key twice.

    Args:
        text: The JSON text; if it is not valid JSON, nothing is said (its
            parser says what is wrong).
        what: What the text is, for the message, e.g. ``"PlanRequest"``.

    Raises:
        InvalidInputError: naming the first key found twice (innermost
            objects are read first), field that key.
    """
    try:
        json.loads(text, object_pairs_hook=_object)
    except _RepeatedKeyError as repeated:
        raise InvalidInputError(
            f"{what}: key {repeated.key!r} is written twice in one object; "
            "only the last would be read: keep one",
            field=repeated.key,
        ) from None
    except (ValueError, RecursionError):  # not JSON: its parser says so
        return


class _RepeatedKeyError(Exception):
    """A key found twice in one object."""

    def __init__(self, key: str) -> None:
        super().__init__(key)
        self.key = key


def _object(pairs: list[tuple[str, Any]]) -> dict[str, Any]:
    """An object from its ``pairs``, refusing a key met twice."""
    seen: dict[str, Any] = {}
    for key, value in pairs:
        if key in seen:
            raise _RepeatedKeyError(key)
        seen[key] = value
    return seen
