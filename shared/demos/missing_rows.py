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
    missing = np.where(
        steps > GAP_STEP * usual, np.maximum(np.rint(steps / usual) - 1, 1), 0
    ).astype(int)
    for k in np.flatnonzero(missing):
        _check_length(int(k), int(missing[k]), usual, times, lines, where, path)
    rows = np.concatenate(([0], np.cumsum(missing + 1)))
    frames = np.empty(int(rows[-1]) + 1)
    frames[rows] = times
    for k in np.flatnonzero(missing):
        inner = np.linspace(times[k], times[k + 1], int(missing[k]) + 2)[1:-1]
        frames[rows[k] + 1 : rows[k + 1]] = inner
    return Frames(frames, rows)


def _check_length(
    k: int,
    count: int,
    usual: float,
    times: FloatArray,
    lines: list[int],
    where: str,
    path: str,
) -> None:
    """Refuse ``count`` frames missing after row ``k`` if over ``LONGEST_GAP``."""
    length = count * usual
    if length <= LONGEST_GAP + _SLACK:
        return
    raise DemoFileError(
        path,
        f"{where}: no rows between line {lines[k]} (t = {times[k]:g} s) and line "
        f"{lines[k + 1]} (t = {times[k + 1]:g} s): {count} frames missing at the "
        f"trial's step of {usual:.4g} s (median), {length:.3g} s; the import "
        f"fills missing frames for at most {LONGEST_GAP:g} s (a smoothing spline "
        "through the frames around them); export the rows between, or leave "
        "the trial out",
        line=lines[k + 1],
        first_line=lines[k],
        missing=count,
    )
