"""Slopes and curvatures at the knots of the path: those of a cubic spline.

The path's quintic pieces take their knot derivatives from the not-a-knot
cubic spline through the path points (the same end conditions as
``scipy.interpolate.CubicSpline``), so the quintic spline *is* that cubic
spline, C2 with accurate derivatives up to the third, until
:class:`~services.timing.path_spline.PathSpline` changes a knot to keep a
joint inside its range. Local estimates (PCHIP-like) were tried first: their
third derivatives were ten to a hundred times the data's, which is what the
jerk limit sees.

The tridiagonal system for the slopes is solved by LAPACK's ``gtsv``.
"""

from __future__ import annotations

import numpy as np
from scipy.linalg import lapack  # type: ignore[import-untyped]

from shared.errors import TimingError


def knot_slopes(values: np.ndarray, widths: np.ndarray) -> np.ndarray:
    """First derivatives of the not-a-knot cubic spline at its knots.

    Args:
        values: Knot values, shape (K, n), K >= 2.
        widths: Knot spacings, shape (K - 1,), all > 0.

    Returns:
        d values / d parameter at each knot, shape (K, n).
    """
    secant = np.diff(values, axis=0) / widths[:, None]
    if len(widths) == 1:
        return np.vstack((secant, secant))
    if len(widths) == 2:
        return _parabola_slopes(secant, widths)
    h = widths
    lower = np.concatenate((h[1:], [h[-1] + h[-2]]))
    diagonal = np.concatenate(([h[1]], 2.0 * (h[:-1] + h[1:]), [h[-2]]))
    upper = np.concatenate(([h[0] + h[1]], h[:-1]))
    rhs = np.empty((len(h) + 1, values.shape[1]))
    rhs[1:-1] = 3.0 * (h[1:, None] * secant[:-1] + h[:-1, None] * secant[1:])
    d0, d1 = h[0] + h[1], h[-1] + h[-2]
    rhs[0] = ((h[0] + 2.0 * d0) * h[1] * secant[0] + h[0] ** 2 * secant[1]) / d0
    rhs[-1] = (h[-1] ** 2 * secant[-2] + (2.0 * d1 + h[-1]) * h[-2] * secant[-1]) / d1
    *_, slopes, info = lapack.dgtsv(lower, diagonal, upper, rhs)
    if info != 0:
        raise TimingError(
            f"the spline through the path is singular (LAPACK gtsv info {info})"
        )
    return np.asarray(slopes)


def _parabola_slopes(secant: np.ndarray, widths: np.ndarray) -> np.ndarray:
    """Slopes of the parabola through three knots, shape (3, n)."""
    h0, h1 = widths
    curve = 2.0 * (secant[1] - secant[0]) / (h0 + h1)
    middle = secant[0] + curve * h0 / 2.0
    return np.vstack((middle - curve * h0, middle, middle + curve * h1))


def knot_curvatures(
    values: np.ndarray, widths: np.ndarray, slopes: np.ndarray
) -> np.ndarray:
    """Second derivatives at the knots of the cubic pieces with ``slopes``, (K, n).

    Each knot takes the curvature the cubic Hermite piece on its right starts
    with (the last knot: the last piece's end curvature); for a cubic spline
    both sides agree.
    """
    secant = np.diff(values, axis=0) / widths[:, None]
    h = widths[:, None]
    out = np.empty_like(values)
    out[:-1] = (6.0 * secant - 4.0 * slopes[:-1] - 2.0 * slopes[1:]) / h
    out[-1] = (-6.0 * secant[-1] + 2.0 * slopes[-2] + 4.0 * slopes[-1]) / h[-1]
    return out


__all__ = ["knot_curvatures", "knot_slopes"]
