"""Checks of a message's sample times: finite, increasing, not absurdly close.

Clock timestamps (Unix time) are times too: only the span is held to a day.

Every timed message (wrist and joint paths, decisions, trajectories, command
frames) checks its times here, once, when it is read: a step of 1e-15 s
turned speeds into NaN deep inside a service (an internal error instead of
a typed one), and a time of 1e308 s overflowed where it became nanoseconds.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

from shared.messages.base import FieldError

#: Smallest step between two samples [s] (a microsecond).
MIN_STEP = 1e-6
#: Largest span of times a message may hold [s] (a day).
MAX_SPAN = 86_400.0
#: Largest time [s]: Unix time in the year 2286, so that clock timestamps
#: pass and a time in nanoseconds still fits MCAP's 64 bits.
MAX_TIME = 1e10


def check_times(
    times: Sequence[float],
    first_above: float | None = None,
    min_step: float = MIN_STEP,
    field: str = "times",
) -> None:
    """Raise ``ValueError`` (a validation error) unless ``times`` [s] are sane.

    Args:
        times: Sample times [s], shape (n,).
        first_above: If given, the first time must be above it [s].
        min_step: Smallest step between samples [s]; 0 for measured times,
            which need only increase.
        field: The message's field that holds them, named by the error.

    Raises:
        FieldError: (a ``ValueError``) about ``field``, naming the first
            sample that is not finite or beyond ``MAX_TIME``, or not after
            the one before by ``min_step`` or more, or a span of times over
            a day.
    """
    for i, t in enumerate(times):
        if not (math.isfinite(t) and abs(t) <= MAX_TIME):
            raise FieldError(
                field,
                f"times[{i}] is {t:g} s: times must be finite and within "
                f"{MAX_TIME:g} s",
            )
    if times and times[-1] - times[0] > MAX_SPAN:
        raise FieldError(
            field,
            f"the times span {times[-1] - times[0]:g} s, more than {MAX_SPAN:g} s "
            f"(a day), from t = {times[0]:.9g} s to t = {times[-1]:.9g} s",
        )
    if first_above is not None and times and not times[0] > first_above:
        raise FieldError(
            field, f"times[0] must be above {first_above:g} s, got {times[0]:g}"
        )
    for i in range(1, len(times)):
        step = times[i] - times[i - 1]
        if not (step > 0.0 and step >= min_step):
            raise FieldError(
                field,
                f"times must increase by at least {min_step:g} s: sample {i} "
                f"(t = {times[i]:.9g} s) comes {step:.3g} s after "
                f"sample {i - 1} (t = {times[i - 1]:.9g} s)",
            )
