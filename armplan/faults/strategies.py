"""Bad request payloads, generated with hypothesis from a valid request.

Each strategy takes a valid request as JSON data (the template) and spoils
it in one way: a value of the wrong type, a NaN or infinity, a huge array,
deep nesting, an unknown field, or bytes that are not JSON at all. A
spoiled request may by chance still be valid (text where a float was, if it
reads as a number); the service then answers it, which is fine too.
:func:`draw` collects examples outside a test, from a fixed seed.
"""

from __future__ import annotations

import json
import math
from collections.abc import Callable
from typing import Any, NamedTuple, TypeVar

from hypothesis import HealthCheck, Phase, given, settings
from hypothesis import seed as with_seed
from hypothesis import strategies as st

#: A JSON value, and a location in one (keys and indices from the root).
Json = Any
Where = tuple[str | int, ...]
T = TypeVar("T")

#: Lengths of the huge arrays: over the 60 000 samples a wrist path may
#: have, and over the suite's 1 MiB payload limit.
HUGE = (10_000, 60_001, 300_000)
#: Depths of the deep nesting (over Python's default recursion limit too).
DEEP = (64, 2_000, 100_000)
#: Values of the wrong type for any field.
WRONG = st.one_of(
    st.text(max_size=12),
    st.none(),
    st.booleans(),
    st.dictionaries(st.text(max_size=4), st.integers(), max_size=2),
    st.lists(st.text(max_size=4), max_size=2),
)
#: A placeholder spliced out of the JSON text for the deep nesting.
_HOLE = "\u0000faults-hole\u0000"


class BadInput(NamedTuple):
    """One spoiled request.

    Attributes:
        kind: How it was spoiled, e.g. ``"not finite"``.
        payload: The bytes sent.
    """

    kind: str
    payload: bytes


def dump(value: Json) -> bytes:
    """JSON bytes, with NaN and infinities as the bare words Python writes."""
    return json.dumps(value, allow_nan=True).encode()


def locations(value: Json, where: Where = ()) -> list[Where]:
    """Every location in ``value``, the root first, then deeper ones."""
    found = [where]
    if isinstance(value, dict):
        for key, item in value.items():
            found += locations(item, (*where, key))
    elif isinstance(value, list):
        for index, item in enumerate(value):
            found += locations(item, (*where, index))
    return found


def _inside_first(found: list[Where]) -> list[Where]:
    """``found`` with the deepest locations first, the root last.

    Hypothesis's first example takes the first element of a
    ``sampled_from``; this way even a few examples reach inside the request.
    """
    return sorted(found, key=len, reverse=True)


def replaced(value: Json, where: Where, new: Json) -> Json:
    """A copy of ``value`` with ``new`` at ``where`` (a missing key is added)."""
    if not where:
        return new
    head, rest = where[0], where[1:]
    if isinstance(value, dict):
        assert isinstance(head, str)
        return {**value, head: replaced(value.get(head), rest, new)}
    assert isinstance(value, list) and isinstance(head, int)
    return [replaced(v, rest, new) if i == head else v for i, v in enumerate(value)]


def at(value: Json, where: Where) -> Json:
    """The value at ``where``."""
    for step in where:
        value = value[step]
    return value


def _numbers(template: Json) -> list[Where]:
    """Locations of numbers (not booleans); a new field if there are none."""
    found = [
        w
        for w in locations(template)
        if isinstance(at(template, w), int | float)
        and not isinstance(at(template, w), bool)
    ]
    return found or [("value",)]


def wrong_type(template: Json) -> st.SearchStrategy[BadInput]:
    """Any value (the whole request too) replaced by one of another type."""
    where = st.sampled_from(_inside_first(locations(template)))
    valid = dump(template)
    return st.builds(
        lambda w, v: BadInput("wrong type", dump(replaced(template, w, v))),
        where,
        WRONG,
    ).filter(lambda bad: bad.payload != valid)  # not a null put over a null


def not_finite(template: Json) -> st.SearchStrategy[BadInput]:
    """A number replaced by NaN, infinity or minus infinity."""
    return st.builds(
        lambda w, v: BadInput("not finite", dump(replaced(template, w, v))),
        st.sampled_from(_numbers(template)),
        st.sampled_from([math.nan, math.inf, -math.inf]),
    )


def huge_array(template: Json) -> st.SearchStrategy[BadInput]:
    """A value replaced by a huge array of numbers, points or text."""
    fill = st.sampled_from([0.5, [0.1, -0.1, 0.05], "x"])
    return st.builds(
        lambda w, n, v: BadInput("huge array", dump(replaced(template, w, [v] * n))),
        st.sampled_from(_inside_first(locations(template))),
        st.sampled_from(HUGE),
        fill,
    )


def nested(depth: int, opener: str) -> str:
    """JSON text nested ``depth`` deep: ``[[[...]]]`` or ``{"a":{"a":...}}``."""
    closer = "]" if opener == "[" else "}"
    inner = "" if opener == "[" else "0"
    return opener * depth + inner + closer * depth


def deep_nesting(template: Json) -> st.SearchStrategy[BadInput]:
    """A value replaced by deeply nested arrays or objects."""

    def spoil(where: Where, depth: int, opener: str) -> BadInput:
        text = dump(replaced(template, where, _HOLE)).decode()
        return BadInput(
            "deep nesting",
            text.replace(json.dumps(_HOLE), nested(depth, opener)).encode(),
        )

    return st.builds(
        spoil,
        st.sampled_from(_inside_first(locations(template))),
        st.sampled_from(DEEP),
        st.sampled_from(["[", '{"a":']),
    )


def unknown_field(template: Json) -> st.SearchStrategy[BadInput]:
    """A field no message has, added to the request or to an object in it."""
    objects = [w for w in locations(template) if isinstance(at(template, w), dict)]

    def spoil(where: Where, name: str, value: Json) -> BadInput:
        return BadInput(
            "unknown field", dump(replaced(template, (*where, name), value))
        )

    return st.builds(
        spoil,
        st.sampled_from(_inside_first(objects) or [()]),
        st.text(min_size=1, max_size=16).map(lambda s: f"unknown-{s}"),
        st.one_of(st.integers(), st.text(max_size=8), st.none()),
    )


def malformed(template: Json) -> st.SearchStrategy[BadInput]:
    """Bytes that are not the request's JSON: cut short, random, not UTF-8."""
    valid = dump(template)
    return st.one_of(
        st.integers(1, max(len(valid) - 1, 1)).map(lambda n: valid[:n]),
        st.binary(min_size=1, max_size=64),
        st.binary(max_size=16).map(lambda b: b"\xff\xfe" + b),
        st.just(valid + b"}"),
    ).map(lambda payload: BadInput("malformed", payload))


#: Every way of spoiling a request, by kind.
SPOILERS: dict[str, Callable[[Json], st.SearchStrategy[BadInput]]] = {
    "wrong type": wrong_type,
    "not finite": not_finite,
    "huge array": huge_array,
    "deep nesting": deep_nesting,
    "unknown field": unknown_field,
    "malformed": malformed,
}


def bad_inputs(template: Json) -> st.SearchStrategy[BadInput]:
    """A request spoiled in any of the ways above."""
    return st.one_of([spoil(template) for spoil in SPOILERS.values()])


def draw(strategy: st.SearchStrategy[T], count: int, seed: int) -> list[T]:
    """``count`` examples of ``strategy`` from ``seed``: the same ones every run."""
    found: list[T] = []

    @with_seed(seed)
    @settings(
        max_examples=count,
        database=None,
        deadline=None,
        phases=[Phase.generate],
        suppress_health_check=list(HealthCheck),
    )
    @given(strategy)
    def keep(example: T) -> None:
        found.append(example)

    keep()
    return found
