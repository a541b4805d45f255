"""Times are seconds: the sample rate that shows they are not.

Times in milliseconds read as seconds make the sample rate a thousand times
too slow (100 Hz reads as 0.1 Hz, a 0.5 s reach lasts 500 s). Nothing armplan
reads is sampled outside ``MIN_SAMPLE_RATE`` to ``MAX_SAMPLE_RATE``
(``shared.messages.motion_model``; motion capture runs at 50-1000 Hz, the
planner's paths at 100 Hz), so a median rate outside it means times in
another unit. Demonstrations (``shared.demos.sample_rate.check_seconds``)
and wrist paths (``WristPath``, whichever way they come: a CSV file, a
``PlanRequest`` or ``DecideRequest`` over Zenoh) are refused here, in the
same words.
"""

from __future__ import annotations

from shared.messages.motion_model import MAX_SAMPLE_RATE, MIN_SAMPLE_RATE

#: Milliseconds per second: how many times too slow times in milliseconds
#: read as seconds make the sample rate.
MILLISECONDS = 1000.0

#: What to do with times in milliseconds, unless the caller knows better.
DIVIDE = f"divide them by {MILLISECONDS:g} (times are in seconds)"


def not_seconds(
    step: float,
    what: str,
    sampled: str,
    milliseconds_fix: str = DIVIDE,
    seconds_fix: str | None = None,
) -> str:
    """Why times ``step`` apart (median) are not seconds; ``""`` if they may be.

    Args:
        step: The median step between consecutive times, read as [s] (> 0).
        what: Whose times, for the message, e.g. ``"the wrist path"``.
        sampled: What is sampled in the range, e.g. ``"demonstrations"``.
        milliseconds_fix: What to do when the times look like milliseconds.
        seconds_fix: What to do when they look like seconds taken for
            milliseconds (a thousand times too fast); ``None``: say nothing.

    Returns:
        ``""`` if one over ``step`` lies in ``MIN_SAMPLE_RATE`` to
        ``MAX_SAMPLE_RATE`` [Hz]; else the message, naming ``what``, the step
        and the rate, and saying what to do when milliseconds would explain it.
    """
    rate = 1.0 / step
    if MIN_SAMPLE_RATE <= rate <= MAX_SAMPLE_RATE:
        return ""
    hint = "times must be in seconds"
    if MIN_SAMPLE_RATE <= MILLISECONDS * rate <= MAX_SAMPLE_RATE:
        hint = f"these look like milliseconds: {milliseconds_fix}"
    elif seconds_fix and MIN_SAMPLE_RATE <= rate / MILLISECONDS <= MAX_SAMPLE_RATE:
        hint = f"the file's times look like seconds: {seconds_fix}"
    return (
        f"{what}: the times step {step:.4g} apart (median), a sample rate of "
        f"{rate:.4g} Hz if they are seconds; {sampled} are sampled at "
        f"{MIN_SAMPLE_RATE:g} to {MAX_SAMPLE_RATE:g} Hz: {hint}"
    )
