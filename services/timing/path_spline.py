"""The joint path as a C2 quintic Hermite spline q(u) through every path point.

Each piece is a quintic in its local coordinate ``tau = (u - u_k) / h_k``
with the knots' values, slopes and curvatures from
:mod:`services.timing.knot_derivatives` (those of the cubic spline through the
points, so the quintic spline is that cubic spline unless a knot is changed to
keep a joint in its range, see below).

:meth:`PathSpline.bounds` gives guaranteed upper bounds of |q'|, |q''| and
|q'''| on every piece (samples plus a Lipschitz margin, not estimates); the
timing derives its speed limits from them, which makes "within limits" hold
on the whole curve, between samples too, so resampling it (the bridge's 25
fps frames) stays within limits as well.

Range: a quintic piece lies within the hull of its Bezier control points.
Where a piece's control points leave a joint's range (a cubic spline overshoots
where a joint stops against its limit), that joint's slope and curvature are
set to zero at both of the piece's knots, which puts every control point of
the piece on one of its two path points, both within range. The curve still
passes through every path point.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from services.timing.knot_derivatives import knot_curvatures, knot_slopes


class SplineSample(NamedTuple):
    """q(u) and its derivatives at parameter values.

    Attributes:
        position: q [rad], shape (m, n).
        first: dq/du [rad per unit of u], shape (m, n).
        second: d2q/du2, shape (m, n).
        third: d3q/du3, shape (m, n).
        piece: Piece of each value, shape (m,).
        tau: Fraction of the way through its piece, shape (m,).
    """

    position: np.ndarray
    first: np.ndarray
    second: np.ndarray
    third: np.ndarray
    piece: np.ndarray
    tau: np.ndarray


class DerivativeBounds(NamedTuple):
    """Upper bounds of |q'|, |q''|, |q'''| on each piece; each shape (K - 1, n)."""

    first: np.ndarray
    second: np.ndarray
    third: np.ndarray


class PathSpline:
    """A C2 quintic spline through path points, with guaranteed derivative bounds.

    Attributes:
        knots: Parameter value at each path point, shape (K,), from 0.
        widths: Knot spacings, shape (K - 1,).
        control: Bezier control points per piece, shape (K - 1, 6, n).
        lower, upper: The ranges the curve stays in [rad], shape (n,).
    """

    def __init__(
        self,
        points: np.ndarray,
        widths: np.ndarray,
        lower: np.ndarray,
        upper: np.ndarray,
    ) -> None:
        """Spline through ``points`` (K, n) with spacings ``widths`` (K - 1,).

        ``lower``/``upper`` (n,) are the ranges the curve must stay in; the
        points themselves must be within them.
        """
        self.widths = np.asarray(widths, dtype=float)
        self.lower, self.upper = lower, upper
        self.knots = np.concatenate(([0.0], np.cumsum(self.widths)))
        slope = knot_slopes(points, self.widths)
        curve = knot_curvatures(points, self.widths, slope)
        self.control = _control_points(points, slope, curve, self.widths)
        outside = np.any(
            (self.control < lower) | (self.control > upper), axis=1
        )  # (K - 1, n)
        if np.any(outside):
            flat = np.zeros((len(points), points.shape[1]), dtype=bool)
            flat[:-1] |= outside
            flat[1:] |= outside
            slope[flat], curve[flat] = 0.0, 0.0
            self.control = _control_points(points, slope, curve, self.widths)
        self._power = _power_basis(self.control)
        # h^-d per piece and derivative order d, shape (K - 1, 4): d/du = d/dtau / h
        self._scale = self.widths[:, None] ** -np.arange(4.0)
        self._bounds: DerivativeBounds | None = None

    @property
    def length(self) -> float:
        """Parameter value at the last path point."""
        return float(self.knots[-1])

    def bounds(self) -> DerivativeBounds:
        """Bounds of |q'|, |q''|, |q'''| per piece and joint, each (K - 1, n).

        Each derivative f is evaluated at ``BOUND_SAMPLES`` + 1 evenly spaced
        points of every piece. On a stretch [a, b] between two of them,
        |f| <= (|f(a)| + |f(b)|) / 2 + L (b - a) / 2, where L bounds |f'| on
        the piece: exact for the fourth derivative (linear), then each bound
        serves the derivative below it.
        """
        if self._bounds is None:
            self._bounds = self._compute_bounds()
        return self._bounds

    def _compute_bounds(self) -> DerivativeBounds:
        shape = (self._power.shape[0], self._power.shape[2])
        flat = np.swapaxes(self._power, 0, 1).reshape(6, -1)  # (6, P)
        samples = np.abs(_GRID @ flat).reshape(3, BOUND_SAMPLES + 1, -1)
        peak = (samples[:, 1:] + samples[:, :-1]).max(axis=1) * 0.5  # (3, P)
        lipschitz = np.maximum(
            np.abs(24.0 * flat[4]), np.abs(24.0 * flat[4] + 120.0 * flat[5])
        )
        margin = 0.5 / BOUND_SAMPLES
        third = peak[2] + margin * lipschitz
        second = peak[1] + margin * third
        first = peak[0] + margin * second
        h = self.widths[:, None]
        return DerivativeBounds(
            first.reshape(shape) / h,
            second.reshape(shape) / h**2,
            third.reshape(shape) / h**3,
        )

    def locate(self, u: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Piece index (m,) and local coordinate tau in [0, 1] (m,) of ``u``."""
        piece = np.searchsorted(self.knots, u, side="right") - 1
        piece = np.clip(piece, 0, len(self.widths) - 1)
        tau = np.clip((u - self.knots[piece]) / self.widths[piece], 0.0, 1.0)
        return piece, tau

    def evaluate(self, u: np.ndarray) -> SplineSample:
        """q and its first three derivatives at parameter values ``u`` (m,)."""
        piece, tau = self.locate(np.asarray(u, dtype=float))
        powers = tau[:, None] ** np.arange(6)  # (m, 6)
        basis = (powers @ _DERIVATIVE_BASIS).reshape(len(tau), 4, 6)
        values = basis @ self._power[piece]  # (m, 4, n)
        values *= self._scale[piece][:, :, None]
        position, first, second, third = np.moveaxis(values, 1, 0)
        # The curve is inside the ranges (control points); clip float round-off.
        np.clip(position, self.lower, self.upper, out=position)
        return SplineSample(position, first, second, third, piece, tau)


def _control_points(
    points: np.ndarray, slope: np.ndarray, curve: np.ndarray, widths: np.ndarray
) -> np.ndarray:
    """Bezier control points of each quintic Hermite piece, shape (K - 1, 6, n)."""
    h = widths[:, None]
    p0, p1 = points[:-1], points[1:]
    m0, m1 = slope[:-1] * h, slope[1:] * h
    c0, c1 = curve[:-1] * h**2, curve[1:] * h**2
    return np.stack(
        (
            p0,
            p0 + m0 / 5.0,
            p0 + 2.0 * m0 / 5.0 + c0 / 20.0,
            p1 - 2.0 * m1 / 5.0 + c1 / 20.0,
            p1 - m1 / 5.0,
            p1,
        ),
        axis=1,
    )


#: Intervals per piece at which :meth:`PathSpline.bounds` samples derivatives.
BOUND_SAMPLES = 16


def _derivative_rows(order: int) -> np.ndarray:
    """Rows giving the ``order``-th tau-derivative of a quintic on the bound grid.

    Shape (BOUND_SAMPLES + 1, 6): row g times the power-basis coefficients is
    the derivative at tau = g / BOUND_SAMPLES.
    """
    tau = np.linspace(0.0, 1.0, BOUND_SAMPLES + 1)[:, None]
    j = np.arange(6)[None, :]
    factor = np.ones((1, 6))
    for k in range(order):
        factor = factor * (j - k)
    return factor * tau ** np.maximum(j - order, 0)


#: Bernstein (degree 5) to power basis: a = BERNSTEIN_TO_POWER @ P.
BERNSTEIN_TO_POWER = np.array(
    [
        [1, 0, 0, 0, 0, 0],
        [-5, 5, 0, 0, 0, 0],
        [10, -20, 10, 0, 0, 0],
        [-10, 30, -30, 10, 0, 0],
        [5, -20, 30, -20, 5, 0],
        [-1, 5, -10, 10, -5, 1],
    ],
    dtype=float,
)


#: The first three tau-derivatives on the bound grid stacked, shape (3 (g + 1), 6):
#: times power-basis coefficients (6, P) it gives them all at once.
_GRID = np.vstack([_derivative_rows(order) for order in (1, 2, 3)])


def _power_basis(control: np.ndarray) -> np.ndarray:
    """Power-basis coefficients in tau, shape (K - 1, 6, n), from control points."""
    return BERNSTEIN_TO_POWER @ control


def _derivative_basis() -> np.ndarray:
    """Matrix D, shape (6, 24), from tau's powers to derivative rows.

    ``tau ** arange(6) @ D``, reshaped (4, 6), holds the rows that turn
    power-basis coefficients into the value and its first three derivatives.
    """
    out = np.zeros((6, 4, 6))
    for order in range(4):
        for j in range(order, 6):
            out[j - order, order, j] = np.prod(np.arange(j - order + 1, j + 1))
    return out.reshape(6, 24)


_DERIVATIVE_BASIS = _derivative_basis()


__all__ = ["DerivativeBounds", "PathSpline", "SplineSample"]
