"""A dict in a message stops validating at its first wrong value, as a list does.

``shared.messages.fail_fast`` set pydantic's ``fail_fast`` on lists,
tuples and sets but not on dicts, which take it too: a 16 MB ``ik/path``
request (``PathIKRequest``, within ``max_payload``) whose decision's
``matrices`` held a million wrong values kept a million errors: 1.2 GB and
3.5 s to parse, where a list of as many stops at its first.
"""

from __future__ import annotations

import importlib
import json
import pkgutil
from collections.abc import Iterator
from typing import Any

import pytest

import shared.messages
from shared.errors import InvalidInputError
from shared.messages import Decision, Message, parse

#: Wrong values in one dict.
VALUES = 1000
#: The pydantic-core schema types of containers that take ``fail_fast``.
CONTAINERS = ("list", "tuple", "set", "frozenset", "dict")


def _decision(matrices: dict[str, Any]) -> str:
    """A Decision's JSON, valid but for ``matrices``."""
    return json.dumps(
        {
            "arm": "right",
            "times": [0.0],
            "primitives": ["S_R E_P W_P"],
            "candidates": ["S_R E_P W_P"],
            "g": [[0.0]],
            "matrices": matrices,
        }
    )


def test_a_dict_stops_at_its_first_wrong_value() -> None:
    """Its first wrong value is named, the others are not looked at."""
    wrong = {f"k{i}": "x" for i in range(VALUES)}
    with pytest.raises(InvalidInputError) as refused:
        parse(Decision, _decision(wrong))
    assert refused.value.message == (
        "invalid Decision: matrices.k0: Input should be a valid array (got 'x')"
    )


def _messages(cls: type[Message]) -> Iterator[type[Message]]:
    for sub in cls.__subclasses__():
        yield sub
        yield from _messages(sub)


def _containers(schema: Any, where: str) -> Iterator[tuple[str, dict[str, Any]]]:
    """Every container schema within ``schema`` and where it is."""
    if isinstance(schema, dict):
        if schema.get("type") in CONTAINERS:
            yield where, schema
        for key, value in schema.items():
            yield from _containers(value, f"{where}/{key}")
    elif isinstance(schema, list):
        for k, value in enumerate(schema):
            yield from _containers(value, f"{where}[{k}]")


def test_every_container_of_every_message_fails_fast() -> None:
    """No list, tuple, set or dict of any message keeps an error per item."""
    for module in pkgutil.iter_modules(shared.messages.__path__):
        importlib.import_module(f"shared.messages.{module.name}")
    slow = [
        f"{cls.__name__}{where}"
        for cls in set(_messages(Message))
        for where, schema in _containers(cls.__pydantic_core_schema__, "")
        if not schema.get("fail_fast")
    ]
    assert slow == []
