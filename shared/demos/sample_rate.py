"""Demonstration times are seconds: the sample rate that shows they are not.

A recording whose times are in milliseconds, read as seconds, is sampled a
thousand times too slowly (100 Hz reads as 0.1 Hz): ``check_seconds``
refuses a median rate outside the motion model's range
(``shared.messages.seconds``, which holds wrist paths to the same range in
the same words). ``armplan demos import`` checks each CSV trial with it,
and ``armplan fit`` the whole set, so the two refuse the same times in the
same words.

Nor is a demonstration sampled below ``MIN_CAPTURE_RATE``: a time column
of frame numbers (0, 1, 2, ...) read as seconds makes 1 Hz, within the
motion model's range, and a 136-sample reach read as 136 s was refused only
later, as mostly still. ``check_capture_rate`` refuses such a recording
on import (one over its median step below 20 Hz, which a hole of missing
rows cannot move), asking whether the times are frame numbers (``armplan fit``
takes what the demonstration files hold: a sparser sampling of a reach is
still one rate).

``check_one_rate`` refuses demonstrations sampled at several rates: the
network counts transitions from one sample to the next, so a step of 1 ms
in one file and of 10 ms in another would be counted as one step.

A trial's rate is one over its median step across half the trial
(``fitted_rate``), not one over its median step: CSV times written to
the millisecond round a 120 Hz capture's steps (8.33 ms) to 8 and 9 ms,
whose median made 125 Hz, and the same session's C3D (120 Hz) and CSV were
refused as two rates (240 Hz read as 250, 150 Hz as 142.9). Nor is it the
samples' count over the span, (n - 1) / (t[-1] - t[0]): a synthetic reach's
last sample is at its duration, up to half a step off the grid, which made
an 80-sample trial's rate 99.4 Hz. The median step is kept for telling
seconds from milliseconds, which a few odd steps must not sway. Frames
missing from a CSV trial are put back before (``missing_rows``).
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


#: Slowest sample rate [Hz] of a demonstration: motion capture samples at
#: 50 to 1000 Hz (the paper's at 100 Hz); a 20 Hz capture still has 11
#: samples in the paper's quickest mean reach (0.55 s, Table 4).
MIN_CAPTURE_RATE = 20.0
#: Relative slack for a rate that is one over a float step (20 Hz reads as
#: 19.999999999999996).
_RATE_SLACK = 1e-9


def check_seconds(
    times: Iterable[FloatArray],
    what: str,
    milliseconds_fix: str = DIVIDE,
    seconds_fix: str | None = None,
) -> float:
    """The sample rate [Hz] of ``times``, refused if they are not seconds.

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
        The trials' rate together [Hz] (``fitted_rate``).

    Raises:
        InvalidInputError: (field ``times``) if one over the median step is
            outside ``MIN_SAMPLE_RATE`` to ``MAX_SAMPLE_RATE``, naming
            ``what``, the step and the rate, and saying what to do
            (``milliseconds_fix``) when milliseconds would explain it
            (``shared.messages.seconds``).
    """
    times = list(times)
    step = float(np.median(np.concatenate([np.diff(t) for t in times])))
    problem = not_seconds(step, what, "demonstrations", milliseconds_fix, seconds_fix)
    if problem:
        raise InvalidInputError(problem, field="times", step=step, rate=1.0 / step)
    return fitted_rate(times)


def check_capture_rate(times: FloatArray, what: str) -> None:
    """Refuse a recorded trial sampled below ``MIN_CAPTURE_RATE``.

    Judged on one over the median step, which rows left out cannot move
    (``missing_rows`` then fills or refuses them): one over the wide step
    (``fitted_rate``) read 15.97 Hz for a 100 Hz trial with a 1 s hole,
    and asked whether its times were frame numbers.

    Args:
        times: The trial's increasing times [s], shape (n,), n >= 2.
        what: Whose times, for the message, e.g. ``"trial 3 (lines 2-31)"``.

    Raises:
        InvalidInputError: (field ``times``) naming ``what``, the median
            step and the rate, and asking whether the times are frame
            numbers.
    """
    step = float(np.median(np.diff(times)))
    rate = 1.0 / step
    if rate >= MIN_CAPTURE_RATE * (1.0 - _RATE_SLACK):
        return
    raise InvalidInputError(
        f"{what}: the times step {step:.4g} s apart (median), a sample rate "
        f"of {rate:.4g} Hz; motion capture samples at {MIN_CAPTURE_RATE:g} "
        "Hz or more: are these frame numbers? Times must be in seconds (a "
        "frame's number over the capture's rate)",
        field="times",
        step=step,
        rate=rate,
    )


def fitted_rate(times: Iterable[FloatArray]) -> float:
    """The sample rate [Hz] of one or more trials: one over their wide step.

    A trial of n samples spans ``m = (n - 1) // 2`` steps from each of its
    first ``n - m`` samples; the rate is one over the median of those spans
    over ``m``, all trials' together. Rounding the times moves a span by
    at most one rounding step, a ``m``-th of a step each; a last sample off
    the grid (a synthetic reach ends at its duration) moves only the last
    span, which the median ignores, so a regular clock reads exactly.

    Args:
        times: Increasing times [s] of each trial, shape (n,); together at
            least one step.

    Returns:
        One over the median wide step [Hz].
    """
    steps = []
    for t in times:
        m = max((len(t) - 1) // 2, 1)
        steps.append((t[m:] - t[:-m]) / m)
    return 1.0 / float(np.median(np.concatenate(steps)))


#: Largest relative difference of two trials' sample rates taken as one
#: rate (a capture's clock jitters; 100 and 120 Hz are two rates).
SAME_RATE = 0.02


def check_one_rate(trials: Sequence[Trial]) -> None:
    """Refuse trials sampled at different rates (each its ``fitted_rate``).

    Args:
        trials: The demonstrations' trials (times [s], each shape (n,)).

    Raises:
        InvalidInputError: (field ``times``) if a trial's rate differs from
            the first's by more than ``SAME_RATE``, naming each file (or, for
            trials made here, subject) with its rates [Hz].
    """
    rates = [fitted_rate([t.times]) for t in trials]
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
