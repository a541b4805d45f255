"""Rows missing from a CSV trial: frames of no marker, filled or refused.

A CSV export that leaves out the rows where the subject was hidden (or a
trial cut from a longer one) steps over the missing frames in one time
step. Joined as they were, a trial at 100 Hz with rows 0.45-0.94 s deleted
had a 0.51 s hole counted as one sample step, and its wrist jumped 125 mm
between two samples. ``missing_frames`` takes a step of more than
``GAP_STEP`` times the trial's median step for missing frames, as many as
fit at that median step, and puts frames there with every marker missing:
``marker_gaps`` then fills them as it fills empty cells, and the trial's
steps stay those of one rate. Missing frames that last longer than
``LONGEST_GAP`` are refused here, naming the lines on both sides.

Times written to a resolution r (the millisecond) round an even clock's
steps to the two multiples of r around its period p: above 500 Hz, 1 and
2 ms, a median of 1 ms, and every 2 ms step had read as a missing frame
(910 rows at 700 Hz made 1300 frames, 390 "filled"; 1248 at 960 Hz the
same 1300). A one-frame step reads at most p + r, and the median at
least p - r, so a step up to the median plus r may be one frame; such a
step is rounding's, not a missing frame, where the run of rows around
it (between longer steps, which are holes at any rounding) holds at
least two of them and its times are one even clock rounded to r: some
line within r / 2 of every one (``_rounded_steps``). A single such step
is taken for a missing frame: one step cannot show a clock's pattern
(and a 100 Hz clock with one missing frame steps exactly so). The
resolution is the least difference between the values of the steps at
most twice the median (``resolution``); the missing frames are then
counted at the mean of the run's one-frame steps, the period, not at the
median (1 ms at 700 Hz). Left undecidable: missing frames spread as
evenly as a rounded clock's long steps are that clock.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from shared.demos.marker_gaps import LONGEST_GAP
from shared.demos.rotations import FloatArray
from shared.errors import DemoFileError

#: A step longer than this many times the trial's median step has frames
#: missing: a capture's clock jitters far less, and times rounded to the
#: millisecond step at most 1.5 times the median (2 and 3 ms at 400 Hz).
GAP_STEP = 1.6
#: Halvings of the periods searched for the line nearest a run's times.
_BISECTIONS = 100
#: Slack [s] for a gap's length, a product of floats (as in ``marker_gaps``).
_SLACK = 1e-9


class Frames(NamedTuple):
    """A trial's frames with the missing ones put back.

    Attributes:
        times: Each frame's time [s], shape (m,), m >= the rows' n.
        rows: Which frame each row is, shape (n,), increasing.
    """

    times: FloatArray
    rows: np.ndarray


def missing_frames(
    times: FloatArray, lines: list[int], where: str, path: str
) -> Frames:
    """The trial's frames, with those its rows step over put back.

    Args:
        times: The rows' times [s], shape (n,), n >= 2, increasing.
        lines: Each row's line in the file (from 1), for messages.
        where: The trial named for messages, e.g. ``"trial 3"``.
        path: The file, for messages.

    Returns:
        The frames' times (a missing frame's evenly spaced between the rows
        around it) and which frame each row is.

    Raises:
        DemoFileError: naming the two lines, their times and how long the
            missing frames last, if they last more than ``LONGEST_GAP``.
    """
    steps = np.diff(times)
    usual = float(np.median(steps))
    rounded = _rounded_steps(times)
    measure = "median"
    if rounded.any():
        usual = float(np.mean(steps[rounded | (steps <= usual)]))
        measure = "mean over its rounded times"
    long = (steps > GAP_STEP * usual) & ~rounded
    missing = np.where(long, np.maximum(np.rint(steps / usual) - 1, 1), 0).astype(int)
    for k in np.flatnonzero(missing):
        count = int(missing[k])
        _check_length(int(k), count, (usual, measure), times, lines, where, path)
    rows = np.concatenate(([0], np.cumsum(missing + 1)))
    frames = np.empty(int(rows[-1]) + 1)
    frames[rows] = times
    for k in np.flatnonzero(missing):
        inner = np.linspace(times[k], times[k + 1], int(missing[k]) + 2)[1:-1]
        frames[rows[k] + 1 : rows[k + 1]] = inner
    return Frames(frames, rows)


def resolution(times: FloatArray) -> float:
    """The time column's resolution [s]: its steps' values' least difference.

    Of the steps at most twice the median: a column rounded coarser than
    its median step cannot be read, and a longer step is not one frame
    (two holes' steps differ by anything). 0 if every such step has one
    value (to ``_SLACK``): times written to the millisecond at 700 Hz step
    1 and 2 ms, a resolution of 1 ms; at 100 Hz all step 10 ms, 0.
    """
    steps = np.diff(times)
    steps = steps[steps <= 2.0 * np.median(steps) + _SLACK]
    values = np.unique(np.rint(steps / _SLACK)) * _SLACK
    return float(np.min(np.diff(values))) if len(values) > 1 else 0.0


def _rounded_steps(times: FloatArray) -> np.ndarray:
    """The long steps that rounding made, not missing frames, shape (n - 1,).

    A step longer than ``GAP_STEP`` times the median but by at most the
    time column's resolution r is rounding's if the run of rows around it
    (between steps longer than that) has at least two such steps and is one
    even clock rounded to r: a line within r / 2 of every row's time.
    """
    steps = np.diff(times)
    usual = float(np.median(steps))
    step = resolution(times)
    doubtful = (steps > GAP_STEP * usual) & (steps <= usual + step + _SLACK)
    rounded = np.zeros(len(steps), dtype=bool)
    clear = np.flatnonzero(steps > usual + step + _SLACK)
    for lo, hi in zip(np.r_[0, clear + 1], np.r_[clear, len(steps)], strict=True):
        run = times[lo : hi + 1]
        if doubtful[lo:hi].sum() >= 2 and _line_spread(run) <= step + _SLACK:
            rounded[lo:hi] = doubtful[lo:hi]
    return rounded


def _line_spread(times: FloatArray) -> float:
    """The least spread [s] of ``times[k] - k p`` over periods p.

    Twice the farthest time from the line that best meets them all
    (minimax). The spread is convex in p: bisected on its slope, the
    frame of the latest time's most ahead less that of the most behind.
    """
    frames = np.arange(len(times))
    low, high = float(np.diff(times).min()), float(np.diff(times).max())
    for _ in range(_BISECTIONS):
        period = 0.5 * (low + high)
        off = times - frames * period
        if np.argmin(off) > np.argmax(off):
            high = period
        else:
            low = period
    off = times - frames * 0.5 * (low + high)
    return float(off.max() - off.min())


def _check_length(
    k: int,
    count: int,
    step: tuple[float, str],
    times: FloatArray,
    lines: list[int],
    where: str,
    path: str,
) -> None:
    """Refuse ``count`` frames missing after row ``k`` if over ``LONGEST_GAP``."""
    usual, measure = step
    length = count * usual
    if length <= LONGEST_GAP + _SLACK:
        return
    raise DemoFileError(
        path,
        f"{where}: no rows between line {lines[k]} (t = {times[k]:g} s) and line "
        f"{lines[k + 1]} (t = {times[k + 1]:g} s): {count} frames missing at the "
        f"trial's step of {usual:.4g} s ({measure}), {length:.3g} s; the import "
        f"fills missing frames for at most {LONGEST_GAP:g} s (a smoothing spline "
        "through the frames around them); export the rows between, or leave "
        "the trial out",
        line=lines[k + 1],
        first_line=lines[k],
        missing=count,
    )
