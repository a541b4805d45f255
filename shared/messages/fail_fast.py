"""Lists and dicts in a message stop validating at their first wrong item.

pydantic validates every item of a list and keeps an error for each wrong
one (about 570 bytes apiece, before its Python form): a 16 MB request,
within the bus's ``max_payload``, of 8 million wrong numbers took a
service over 6 GB and minutes, and a list far longer than its
``max_length`` was validated item by item before being refused (a 15 MB
list of empty objects as a motion model's ``variables``: 7 GB in the
decide service). With ``fail_fast`` a list stops at its first wrong item:
that item's errors are kept (all of them, so a misspelt key is still
found), the other fields are still validated. A dict takes it too: a
million wrong values in a decision's ``matrices`` (16 MB, an ``ik/path``
request) kept as many errors: 1.2 GB to parse.
"""

from __future__ import annotations

from typing import Any

#: The pydantic-core schema types that take ``fail_fast`` (a deque is
#: validated as a list).
CONTAINERS = frozenset({"list", "tuple", "set", "frozenset", "dict"})


def fail_fast(schema: Any) -> Any:
    """``schema`` (a pydantic core schema) with ``fail_fast`` on every list and dict.

    Changed in place and returned. Nested models keep their own schemas
    (each ``Message`` class applies this to its own).
    """
    if isinstance(schema, dict):
        if schema.get("type") in CONTAINERS:
            schema["fail_fast"] = True
        for value in schema.values():
            fail_fast(value)
    elif isinstance(schema, list):
        for value in schema:
            fail_fast(value)
    return schema
