"""What a marker did over a short gap: a smoothing spline, not one through noise.

Capture software fills a gap with a spline through the frames around it.
A spline through every frame (``CubicSpline``) follows each frame's jitter
and swings it into the gap: over 0.1 s of a quick reach (0.4 m in 0.55 s)
with 1 mm of marker noise it filled positions 13 mm off at 250 Hz and 28 mm
at 500 Hz (median of the worst frame; up to 57 mm), and a thumb marker so
filled lay 47 mm off the forearm's axis and the trial was refused.

``gap_positions`` fits a smoothing cubic spline to the frames within
``SIDE_GAPS`` gap lengths (at least ``SIDE_FRAMES`` frames) on each side,
its smoothing chosen by generalised cross-validation, which weighs how
well it meets the frames against how far it bends: it follows the reach,
not the noise. It is read at the missing frames' times, so it meets the
frames at the gap's edges within their noise. A track with no noise to
speak of (``marker_noise`` under ``NOISE_FLOOR``: synthetic, or smoothed
on export) is interpolated instead, which is exact there.
"""

from __future__ import annotations

import numpy as np
from scipy.interpolate import (  # type: ignore[import-untyped]
    CubicSpline,
    make_smoothing_spline,
)

from shared.demos.rotations import FloatArray

#: Frames each side of a gap that the fit uses, in gap lengths ...
SIDE_GAPS = 3
#: ... and at least this many frames each side.
SIDE_FRAMES = 10
#: Marker noise [m] (standard deviation) under which a track is interpolated:
#: a CSV's 0.1 mm rounding is noise of 0.03 mm; skin markers jitter about 1 mm.
NOISE_FLOOR = 5e-5
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


def gap_positions(
    times: FloatArray, track: FloatArray, first: int, last: int, noise: float
) -> FloatArray:
    """The positions [m] over frames ``first``..``last``, shape (k, 3).

    Args:
        times: Frame times [s], shape (n,), increasing.
        track: Positions [m], shape (n, 3), missing (non-finite) at least
            from ``first`` to ``last``, seen at a frame before and after.
        first: The gap's first frame.
        last: The gap's last frame.
        noise: The track's noise [m] (``marker_noise``).
    """
    side = max(SIDE_GAPS * (last - first + 1), SIDE_FRAMES)
    end = min(last + 1 + side, len(times))
    near = np.r_[max(first - side, 0) : first, last + 1 : end]
    near = near[np.isfinite(track[near]).all(axis=1)]
    wanted = times[first : last + 1]
    if noise < NOISE_FLOOR or len(near) < _FEWEST:
        return np.asarray(CubicSpline(times[near], track[near], axis=0)(wanted))
    columns = [
        make_smoothing_spline(times[near], track[near, axis])(wanted)
        for axis in range(track.shape[1])
    ]
    return np.stack(columns, axis=1)
