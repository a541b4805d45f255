"""Where a trial's wrist stops on its way, between two movements: two reaches.

A trial of a rest, a reach, a 0.8 s hold, a second reach to another point
and a hold passed the import's checks of stillness at the start and end
(``reach_span``), and the fit took both reaches as one: the W_R rate was
2.80 /rad instead of about 5.7. A reach does not stop on its way: a
minimum-jerk one slows only at its ends, and the paper's subjects took 0.55
to 1.01 s per reach (Table 4), so a stop of ``PAUSE_LIMIT`` is as long as a
quick reach. A slow-down does not count: the wrist must stay put, and away
from the trial's start and goal (a stop near either is the reach's own end).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from shared.demos.rotations import FloatArray

#: Longest stop [s] of the wrist on its way from start to goal.
PAUSE_LIMIT = 0.5


class Pause(NamedTuple):
    """The wrist still on its way: when it stops and restarts [s], and where.

    ``place`` [m], shape (3,), is the middle of the positions it keeps.
    """

    stops: float
    restarts: float
    place: FloatArray


def mid_pause(
    times: FloatArray, wrist: FloatArray, near: float, away: float
) -> Pause | None:
    """The first stop of ``PAUSE_LIMIT`` or more away from start and goal.

    Still means every position for ``PAUSE_LIMIT`` lies in a box whose
    diagonal is at most ``near``; away means the box's middle is at least
    ``away`` from the first and from the last position.

    Args:
        times: Sample times [s], shape (n,), increasing.
        wrist: Wrist positions [m], shape (n, 3).
        near: Largest spread [m] of a still wrist.
        away: Least distance [m] of the stop from the start and the goal.
    """
    if len(times) < 2:
        return None
    step = float(np.median(np.diff(times)))
    frames = int(np.ceil(PAUSE_LIMIT / step - 1e-9)) + 1
    if frames > len(times):
        return None
    low, high = _window_box(wrist, frames)
    middle = (low + high) / 2
    still = np.linalg.norm(high - low, axis=1) <= near
    still &= np.linalg.norm(middle - wrist[0], axis=1) >= away
    still &= np.linalg.norm(middle - wrist[-1], axis=1) >= away
    starts = np.flatnonzero(still)
    if not starts.size:
        return None
    first = int(starts[0])
    run = np.flatnonzero(~still[first:])
    last = first + (int(run[0]) if run.size else len(still) - first) - 1
    return Pause(float(times[first]), float(times[last + frames - 1]), middle[first])


def _window_box(wrist: FloatArray, frames: int) -> tuple[FloatArray, FloatArray]:
    """Each ``frames`` long window's least and greatest coordinates [m].

    Shapes (n - frames + 1, 3): row ``k`` is the window from sample ``k``.
    """
    windows = np.lib.stride_tricks.sliding_window_view(wrist, frames, axis=0)
    return windows.min(axis=-1), windows.max(axis=-1)
