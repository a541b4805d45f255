"""Demonstration times are seconds: the sample rate that shows they are not.

A recording whose times are in milliseconds, read as seconds, is sampled a
thousand times too slowly (100 Hz reads as 0.1 Hz). No capture of a reach
is sampled outside the motion model's range, ``MIN_SAMPLE_RATE`` to
``MAX_SAMPLE_RATE`` (``shared.messages.motion_model``), so a median rate
outside it means times in another unit. ``armplan demos import`` checks each
CSV trial with ``check_seconds``, and ``armplan fit`` the whole set, so the
two refuse the same times in the same words.
"""

from __future__ import annotations

from collections.abc import Iterable

import numpy as np

from shared.demos.rotations import FloatArray
from shared.errors import InvalidInputError
from shared.messages.motion_model import MAX_SAMPLE_RATE, MIN_SAMPLE_RATE

#: Milliseconds per second: how many times too slow times in milliseconds
#: read as seconds make the sample rate.
MILLISECONDS = 1000.0


#: What to do with times in milliseconds, unless the caller knows better.
DIVIDE = f"divide them by {MILLISECONDS:g} (times are in seconds)"


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
            when milliseconds would explain it.
    """
    step = float(np.median(np.concatenate([np.diff(t) for t in times])))
    rate = 1.0 / step
    if MIN_SAMPLE_RATE <= rate <= MAX_SAMPLE_RATE:
        return rate
    hint = "times must be in seconds"
    if MIN_SAMPLE_RATE <= MILLISECONDS * rate <= MAX_SAMPLE_RATE:
        hint = f"these look like milliseconds: {milliseconds_fix}"
    elif seconds_fix and MIN_SAMPLE_RATE <= rate / MILLISECONDS <= MAX_SAMPLE_RATE:
        hint = f"the file's times look like seconds: {seconds_fix}"
    raise InvalidInputError(
        f"{what}: the times step {step:.4g} apart (median), a sample rate of "
        f"{rate:.4g} Hz if they are seconds; demonstrations are sampled at "
        f"{MIN_SAMPLE_RATE:g} to {MAX_SAMPLE_RATE:g} Hz: {hint}",
        field="times",
        step=step,
        rate=rate,
    )
