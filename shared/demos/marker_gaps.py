"""Frames where a marker is missing: fill a short gap, refuse the rest.

Motion capture loses a marker for a few frames when a camera's view is
blocked; capture software fills such gaps with a spline through the frames
around. The import does the same for a gap of at most ``LONGEST_GAP``
(each marker's gaps apart): a smoothing spline through the frames on each
side, which follows the reach and not the markers' noise (``gap_fill``).
Over 10 missing frames at 100 Hz (0.1 s) it misses a minimum-jerk reach of
0.4 m in 0.55 s (the paper's quickest mean, Table 4, at an adult's scale)
by at most 0.8 mm without noise, wherever the gap falls (over 20 frames by
up to 5.5 mm); with 0.8 mm of marker noise, at 100 to 500 Hz, by at most
3.5 mm (about 1 mm on median, less than one noisy frame's own error). A
spline through every frame had followed the noise into the gap: 13 mm off
at 250 Hz, up to 57 mm at 500 Hz. Frames were once dropped instead, and
the trial joined across the gap as if no time had passed.

A longer gap is refused: what the marker did there is not known. So is a
gap at the trial's start or end, however short: the last frame is the
reach's goal (a wrist hidden for the last 40 % of a trial made frame 59,
48.5 mm short of the goal and the wrist still moving at 0.285 m/s, the
goal) and the first its start; neither can be guessed from one side.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any, NamedTuple

import numpy as np

from shared.demos.gap_fill import filled_track, marker_noise
from shared.demos.rotations import FloatArray
from shared.demos.sample_lines import Lines, line_evidence
from shared.errors import DemoFileError

#: Longest gap [s] (missing frames times the median step) that is filled:
#: 10 frames at the paper's 100 Hz.
LONGEST_GAP = 0.1
#: Slack [s] for the gap's length, which is a product of floats.
_SLACK = 1e-9


def gap_runs(missing: np.ndarray) -> list[tuple[int, int]]:
    """The runs of ``True`` in ``missing`` (shape (n,)): (first, last) frames."""
    edges = np.diff(np.concatenate(([0], missing.astype(np.int8), [0])))
    starts = np.flatnonzero(edges == 1)
    ends = np.flatnonzero(edges == -1) - 1
    return [(int(a), int(b)) for a, b in zip(starts, ends, strict=True)]


def fill_gaps(
    points: dict[str, FloatArray],
    times: FloatArray,
    names: dict[str, str],
    frame: Callable[[int], str],
    where: str,
    path: str,
    *,
    lines: Lines = None,
) -> tuple[dict[str, FloatArray], int]:
    """The tracks with their short gaps filled; how many frames were filled.

    Args:
        points: Marker positions [m] by role, each shape (n, 3); a missing
            sample has a non-finite coordinate.
        times: Frame times [s], shape (n,), increasing.
        names: Each role's marker name, for messages.
        frame: Frame ``k`` named for a message (time, CSV line).
        where: The trial named for messages, e.g. ``"subject 'P01', trial 0"``.
        path: The file, for messages.
        lines: Each frame's line in a CSV file (``sample_lines``), for the
            evidence, or ``None``.

    Raises:
        DemoFileError: naming the file, trial, marker and frames (and in
            the evidence, with ``lines``, their lines), if a marker
            is missing at the trial's first or last frame, or for longer
            than ``LONGEST_GAP``.
    """
    step = float(np.median(np.diff(times))) if len(times) > 1 else 0.0
    filled = np.zeros(len(times), dtype=bool)
    out = {}
    for role, track in points.items():
        missing = np.asarray(~np.isfinite(track).all(axis=1))
        for first, last in gap_runs(missing):
            gap = Gap(first, last, names[role], line_evidence(lines, first, last))
            _check_gap(gap, len(times), step, frame, where, path)
        out[role] = track
        if missing.any():
            gaps = gap_runs(missing)
            out[role] = filled_track(times, track, gaps, marker_noise(track))
            filled |= missing
    return out, int(filled.sum())


class Gap(NamedTuple):
    """A marker's missing frames ``first``..``last``, and their lines' evidence."""

    first: int
    last: int
    marker: str
    lines: dict[str, Any]


def _check_gap(
    gap: Gap,
    frames: int,
    step: float,
    frame: Callable[[int], str],
    where: str,
    path: str,
) -> None:
    """Refuse a gap at an end of the trial's ``frames`` or too long."""
    first, last, marker = gap.first, gap.last, gap.marker
    span = f"from {frame(first)} to {frame(last)}"
    evidence = {"marker": marker, "first_frame": first, "last_frame": last}
    evidence |= gap.lines
    if first == 0 or last == frames - 1:
        end = "first" if first == 0 else "last"
        meaning = "its start" if first == 0 else "the reach's goal"
        raise DemoFileError(
            path,
            f"{where}: marker {marker!r} is missing {span}, the trial's {end} "
            f"frame: the {end} frame is {meaning}, which cannot be guessed from "
            "one side. Crop the trial to frames where every marker is seen, if "
            "the reach is whole there, or fill the gap in the capture software",
            **evidence,
        )
    length = (last - first + 1) * step
    if length > LONGEST_GAP + _SLACK:
        raise DemoFileError(
            path,
            f"{where}: marker {marker!r} is missing for {length:.3g} s, {span}: "
            f"the import fills a gap of at most {LONGEST_GAP:g} s (a smoothing "
            "spline through the frames around it); fill this one in the capture "
            "software, or leave the trial out",
            **evidence,
        )
