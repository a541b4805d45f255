"""Demonstration times are seconds: the sample rate that shows they are not.

A recording whose times are in milliseconds, read as seconds, is sampled a
thousand times too slowly (100 Hz reads as 0.1 Hz): ``check_seconds``
refuses a median rate outside the motion model's range
(``shared.messages.seconds``, which holds wrist paths to the same range in
the same words). ``armplan demos import`` checks each CSV trial with it,
and ``armplan fit`` the whole set, so the two refuse the same times in the
same words.

``check_one_rate`` refuses demonstrations sampled at several rates: the
network counts transitions from one sample to the next, so a step of 1 ms
in one file and of 10 ms in another would be counted as one step.
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from typing import TYPE_CHECKING

import numpy as np

from shared.demos.rotations import FloatArray
from shared.errors import InvalidInputError
from shared.messages.seconds import DIVIDE, not_seconds

if TYPE_CHECKING:
    from shared.demos.trial import Trial


def check_seconds(
    times: Iterable[FloatArray],
    what: str,
    milliseconds_fix: str = DIVIDE,
    seconds_fix: str | None = None,
) -> float:
    """The median sample rate [Hz] of ``times``, refused if they are not seconds.

    Args:
        times: Increasing times [s] of one or more trials, each shape (n,);
            together at least one step.
        what: Whose times, for the message, e.g. ``"trial 3 (lines 2-31)"``.
        milliseconds_fix: What the message tells to do when the times look
            like milliseconds.
        seconds_fix: What it tells to do when they look like seconds taken
            for milliseconds (a thousand times too fast); ``None``: times
            are not converted, say nothing of it.

    Returns:
        One over the median step between consecutive times [Hz].

    Raises:
        InvalidInputError: (field ``times``) if that rate is outside
            ``MIN_SAMPLE_RATE`` to ``MAX_SAMPLE_RATE``, naming ``what``, the
            step and the rate, and saying what to do (``milliseconds_fix``)
            when milliseconds would explain it (``shared.messages.seconds``).
    """
    step = float(np.median(np.concatenate([np.diff(t) for t in times])))
    problem = not_seconds(step, what, "demonstrations", milliseconds_fix, seconds_fix)
    if problem:
        raise InvalidInputError(problem, field="times", step=step, rate=1.0 / step)
    return 1.0 / step


#: Largest relative difference of two trials' sample rates taken as one
#: rate (a capture's clock jitters; 100 and 120 Hz are two rates).
SAME_RATE = 0.02


def check_one_rate(trials: Sequence[Trial]) -> None:
    """Refuse trials sampled at different rates (each its median step's).

    Args:
        trials: The demonstrations' trials (times [s], each shape (n,)).

    Raises:
        InvalidInputError: (field ``times``) if a trial's rate differs from
            the first's by more than ``SAME_RATE``, naming each file (or, for
            trials made here, subject) with its rates [Hz].
    """
    rates = [1.0 / float(np.median(np.diff(t.times))) for t in trials]
    if all(abs(rate / rates[0] - 1.0) <= SAME_RATE for rate in rates):
        return
    found: dict[str, list[float]] = {}
    for trial, rate in zip(trials, rates, strict=True):
        where = found.setdefault(trial.source or f"subject {trial.subject!r}", [])
        if all(abs(rate / seen - 1.0) > SAME_RATE for seen in where):
            where.append(rate)
    listed = "; ".join(
        f"{where} at {' and '.join(f'{rate:.4g}' for rate in sorted(seen))} Hz"
        for where, seen in found.items()
    )
    raise InvalidInputError(
        f"the demonstrations mix sample rates: {listed}. The motion model "
        "counts transitions from one sample to the next, as steps of one "
        "rate: fit the files of each rate apart, or resample them to one rate",
        field="times",
        rates={where: seen for where, seen in found.items()},
    )
