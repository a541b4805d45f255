"""A count with its noun in the right number: "1 message", "2 messages".

Messages for people say how many of something there were; "1 messages"
reads as a bug. :func:`counted` writes the count and the noun, singular
for exactly one and plural otherwise (zero included: "0 messages", as
English has it). :func:`agreeing` gives the word alone, for a noun whose
number is printed elsewhere ("sent 1 of 1 message") or a verb that must
agree ("1 file was", "2 files were").

Neither ever raises: they write the text of errors, and an error while
writing one would hide it. Any count but exactly one takes the plural.
"""

from __future__ import annotations

from typing import SupportsIndex


def agreeing(n: SupportsIndex, singular: str, plural: str | None = None) -> str:
    """``singular`` if ``n`` is 1, else ``plural`` (default: ``singular + "s"``).

    Args:
        n: How many of the thing there are (NumPy integers too).
        singular: The word for one ("message", "was", "is").
        plural: The word for any other number, for words that do not
            just add an "s" ("trajectories", "reaches", "were", "are").
    """
    if n.__index__() == 1:
        return singular
    return plural if plural is not None else singular + "s"


def counted(n: SupportsIndex, singular: str, plural: str | None = None) -> str:
    """``n`` and the noun in its number: ``counted(1, "message")`` -> ``"1 message"``.

    Args:
        n: How many there are (NumPy integers too).
        singular: The noun for one ("message", "trajectory").
        plural: The noun for any other number if not ``singular + "s"``
            ("trajectories", "reaches").
    """
    return f"{n.__index__()} {agreeing(n, singular, plural)}"
