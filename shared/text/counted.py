"""A count with its noun in the right number: "1 message", "2 messages".

Messages for people say how many of something there were; "1 messages"
reads as a bug. :func:`counted` writes the count and the noun, singular
for exactly one and plural otherwise (zero included: "0 messages", as
English has it). :func:`agreeing` gives the word alone, for a noun whose
number is printed elsewhere ("sent 1 of 1 message") or a verb that must
agree ("1 file was", "2 files were").

A negative count is refused with :class:`InvalidInputError`: a count of
things cannot be below zero, so one is a bug in the caller, and no form
of the word would make "-1 messages" true. A ``bool`` is refused too
(``True`` is an ``int`` to Python but never a count), and so is a
``float``, even 1.0: a count is whole; NumPy integers are counts.
"""

from __future__ import annotations

import operator
from typing import SupportsIndex

from shared.errors import InvalidInputError


def _whole(n: object) -> int:
    """``n`` as an ``int`` if it is a whole number (NumPy's included), not a bool."""
    if isinstance(n, bool):
        raise InvalidInputError(f"a count must be a whole number, got {n!r}", field="n")
    try:
        return operator.index(n)  # type: ignore[arg-type]
    except TypeError:
        raise InvalidInputError(
            f"a count must be a whole number, got {n!r}", field="n"
        ) from None


def agreeing(n: SupportsIndex, singular: str, plural: str | None = None) -> str:
    """``singular`` if ``n`` is 1, else ``plural`` (default: ``singular + "s"``).

    Args:
        n: How many of the thing there are (0 or more).
        singular: The word for one ("message", "was", "is").
        plural: The word for any other number, for words that do not
            just add an "s" ("trajectories", "reaches", "were", "are").

    Raises:
        InvalidInputError: ``n`` is negative or not a whole number (a
            ``float`` such as 1.0 included; NumPy integers are fine).
    """
    count = _whole(n)
    if count < 0:
        raise InvalidInputError(f"a count cannot be negative, got {n}", field="n")
    if count == 1:
        return singular
    return plural if plural is not None else singular + "s"


def counted(n: SupportsIndex, singular: str, plural: str | None = None) -> str:
    """``n`` and the noun in its number: ``counted(1, "message")`` -> ``"1 message"``.

    Args:
        n: How many there are (0 or more).
        singular: The noun for one ("message", "trajectory").
        plural: The noun for any other number if not ``singular + "s"``
            ("trajectories", "reaches").

    Raises:
        InvalidInputError: ``n`` is negative or not an ``int``.
    """
    return f"{n} {agreeing(n, singular, plural)}"
