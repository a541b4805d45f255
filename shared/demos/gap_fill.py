"""What a marker did over a short gap: a smoothing spline, not one through noise.

Capture software fills a gap with a spline through the frames around it.
A spline through every frame (``CubicSpline``) follows each frame's jitter
and swings it into the gap: over 0.1 s of a quick reach (0.4 m in 0.55 s)
with 1 mm of marker noise it filled positions 13 mm off at 250 Hz and 28 mm
at 500 Hz (median of the worst frame; up to 57 mm), and a thumb marker so
filled lay 47 mm off the forearm's axis and the trial was refused.

``filled_track`` fits a smoothing cubic spline to the frames within
``SIDE_GAPS`` gap lengths (at least ``SIDE_FRAMES`` frames) on each side,
its smoothing chosen by generalised cross-validation, which weighs how
well it meets the frames against how far it bends: it follows the reach,
not the noise. It is read at the missing frames' times, so it meets the
frames at the gap's edges within their noise. A track with no noise to
speak of (``marker_noise`` under ``NOISE_FLOOR``: synthetic, or smoothed
on export) is interpolated instead, which is exact there.

Gaps whose windows overlap are fitted together, in one window of up to
``MOST_MERGED`` frames, and the smoothing is found by ``smoothing_gcv``:
scipy's own search, one fit per gap and coordinate, took 60-300 ms each,
and 20 trials at 250 Hz with some 40 short gaps per marker imported in
44-56 s (1.3 s before smoothing); now in 1.5-1.7 s (one BLAS thread).
"""

from __future__ import annotations

import numpy as np
from scipy.interpolate import CubicSpline  # type: ignore[import-untyped]

from shared.demos.rotations import FloatArray
from shared.demos.smoothing_gcv import gcv_fit

#: Frames each side of a gap that the fit uses, in gap lengths ...
SIDE_GAPS = 3
#: ... and at least this many frames each side.
SIDE_FRAMES = 10
#: Marker noise [m] (standard deviation) under which a track is interpolated:
#: a CSV's 0.1 mm rounding is noise of 0.03 mm; skin markers jitter about 1 mm.
NOISE_FLOOR = 5e-5
#: Most frames one fit holds when gaps near each other are fitted together:
#: a GCV fit's cost grows as the frames cubed (``smoothing_gcv``), and over
#: about 100 frames the BLAS's threads contend on a busy machine (20 trials
#: at 250 Hz, 40 gaps a marker: 1.6-1.9 s to import with 100, 1.9-6.7 s
#: with 200).
MOST_MERGED = 100
#: Fewest frames a smoothing spline is fitted to (scipy's least).
_FEWEST = 5
#: Standard deviation of a third difference of white noise, in its sigma:
#: sqrt(1 + 9 + 9 + 1).
_THIRD_DIFFERENCE = np.sqrt(20.0)
#: Median absolute value of a standard normal variable.
_MEDIAN_ABS = 0.6745


def marker_noise(track: FloatArray) -> float:
    """The marker's noise [m]: a standard deviation per coordinate.

    Estimated from the third differences of consecutive seen frames (their
    median size), which the noise dominates: a quick reach's jerk changes
    one at 100 Hz by about 0.1 mm, and a third difference of noise of
    sigma has deviation sqrt(20) sigma.

    Args:
        track: Positions [m], shape (n, 3); a missing frame is non-finite.
    """
    third = np.diff(track, n=3, axis=0)
    third = third[np.isfinite(third).all(axis=1)]
    if not third.size:
        return 0.0
    return float(np.median(np.abs(third)) / _MEDIAN_ABS / _THIRD_DIFFERENCE)


def filled_track(
    times: FloatArray, track: FloatArray, gaps: list[tuple[int, int]], noise: float
) -> FloatArray:
    """The track [m] with its gaps filled, shape (n, 3).

    Gaps whose windows overlap are fitted together, in one window of at most
    ``MOST_MERGED`` frames (or one gap's window, if longer).

    Args:
        times: Frame times [s], shape (n,), increasing.
        track: Positions [m], shape (n, 3), missing (non-finite) exactly
            over ``gaps``, each seen at a frame before and after.
        gaps: The gaps' (first, last) frames, in order.
        noise: The track's noise [m] (``marker_noise``).
    """
    out = track.copy()
    for group in _merged(gaps, len(times)):
        near = np.arange(*_span(group, len(times)))
        near = near[np.isfinite(track[near]).all(axis=1)]
        wanted = np.r_[tuple(slice(a, b + 1) for a, b in group)]
        out[wanted] = _fit(times[near], track[near], times[wanted], noise)
    return out


def _window(gap: tuple[int, int], frames: int) -> tuple[int, int]:
    """The frames [lo, hi) a gap's fit uses: ``SIDE_GAPS`` gap lengths each side."""
    first, last = gap
    side = max(SIDE_GAPS * (last - first + 1), SIDE_FRAMES)
    return max(first - side, 0), min(last + 1 + side, frames)


def _span(group: list[tuple[int, int]], frames: int) -> tuple[int, int]:
    """The frames [lo, hi) a group of gaps' fit uses, its windows' union."""
    windows = [_window(gap, frames) for gap in group]
    return min(lo for lo, _ in windows), max(hi for _, hi in windows)


def _merged(gaps: list[tuple[int, int]], frames: int) -> list[list[tuple[int, int]]]:
    """The gaps in groups whose windows overlap, each within ``MOST_MERGED``."""
    groups: list[list[tuple[int, int]]] = []
    for gap in gaps:
        lo, hi = _window(gap, frames)
        if groups:
            start, end = _span(groups[-1], frames)
            if lo < end and hi - start <= MOST_MERGED:
                groups[-1].append(gap)
                continue
        groups.append([gap])
    return groups


def _fit(
    seen: FloatArray, positions: FloatArray, wanted: FloatArray, noise: float
) -> FloatArray:
    """Positions [m] at times ``wanted`` [s] from those seen, shape (k, 3)."""
    if noise < NOISE_FLOOR or len(seen) < _FEWEST:
        return np.asarray(CubicSpline(seen, positions, axis=0)(wanted))
    smooth = gcv_fit(seen, positions).fitted
    return np.asarray(CubicSpline(seen, smooth, axis=0, bc_type="natural")(wanted))
