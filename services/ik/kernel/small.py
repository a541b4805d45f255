"""Vectors as float tuples and tiny dense linear algebra for the IK's hot loop."""

from __future__ import annotations

import math
from collections.abc import Sequence

Vec = tuple[float, float, float]
#: Lower Cholesky factor of a symmetric 3x3: (l00, l10, l11, l20, l21, l22).
Factor3 = tuple[float, float, float, float, float, float]


def sub(a: Vec, b: Vec) -> Vec:
    """a - b."""
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2])


def dot(a: Vec, b: Vec) -> float:
    """a . b for 3-vectors."""
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def cross(a: Vec, b: Vec) -> Vec:
    """a x b."""
    return (
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    )


def norm(a: Vec) -> float:
    """|a| for a 3-vector."""
    return math.sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2])


def normal_solver(
    cols: Sequence[Sequence[float]], free: Sequence[int], damping: float, floor: float
) -> NormalSolver | NormalSolver3:
    """The pseudo-inverse of J's free columns: unrolled for 3 rows, else generic."""
    if free and len(cols[free[0]]) == 3:
        return NormalSolver3(cols, free, damping, floor)
    return NormalSolver(cols, free, damping, floor)


class NormalSolver3:
    """:class:`NormalSolver` unrolled for three task rows (a wrist position).

    Same arguments and methods; about five times faster, which matters in a
    loop that runs for every path point.
    """

    __slots__ = ("cols", "free", "low")

    def __init__(
        self,
        cols: Sequence[Sequence[float]],
        free: Sequence[int],
        damping: float,
        floor: float,
    ) -> None:
        self.cols, self.free = cols, free
        xs = [c[0] for c in cols]
        ys = [c[1] for c in cols]
        zs = [c[2] for c in cols]
        self.low = factor3(xs, ys, zs, list(free), damping, floor)

    def apply(self, v: Sequence[float]) -> list[float]:
        """J+ v, one value per free joint."""
        if self.low is None:
            return [0.0] * len(self.free)
        x0, x1, x2 = solve3(self.low, v[0], v[1], v[2])
        cols = self.cols
        return [cols[k][0] * x0 + cols[k][1] * x1 + cols[k][2] * x2 for k in self.free]

    def times(self, x: Sequence[float]) -> list[float]:
        """J x for x given over all joints (uses the free columns), 3 values."""
        o0 = o1 = o2 = 0.0
        for k in self.free:
            xk = x[k]
            c0, c1, c2 = self.cols[k]
            o0 += c0 * xk
            o1 += c1 * xk
            o2 += c2 * xk
        return [o0, o1, o2]


def factor3(
    xs: list[float],
    ys: list[float],
    zs: list[float],
    free: list[int],
    damping: float,
    floor: float,
) -> Factor3 | None:
    """The factor :class:`NormalSolver3` makes, of columns given by coordinates.

    Column k is (xs[k], ys[k], zs[k]); ``free``, ``damping`` and ``floor`` as
    for :class:`NormalSolver`. ``None`` if even ``floor`` does not make the
    normal matrix positive definite.
    """
    a00 = a10 = a11 = a20 = a21 = a22 = 0.0
    for i in range(len(free)):
        k = free[i]
        x, y, z = xs[k], ys[k], zs[k]
        a00 += x * x
        a10 += y * x
        a11 += y * y
        a20 += z * x
        a21 += z * y
        a22 += z * z
    gram = (a00, a10, a11, a20, a21, a22)
    low = _cholesky3(gram, damping)
    if low is None or math.pow(min(low[0], min(low[2], low[5])), 2.0) < floor:
        low = _cholesky3(gram, floor)
    return low


def solve3(
    low: Factor3 | None, v0: float, v1: float, v2: float
) -> tuple[float, float, float]:
    """x with L L^T x = v for the factor L of :func:`factor3` (zeros without one)."""
    if low is None:
        return 0.0, 0.0, 0.0
    l00, l10, l11, l20, l21, l22 = low
    y0 = v0 / l00
    y1 = (v1 - l10 * y0) / l11
    y2 = (v2 - l20 * y0 - l21 * y1) / l22
    x2 = y2 / l22
    x1 = (y1 - l21 * x2) / l11
    x0 = (y0 - l10 * x1 - l20 * x2) / l00
    return x0, x1, x2


def _cholesky3(
    a: tuple[float, float, float, float, float, float], damping: float
) -> Factor3 | None:
    """Lower factor of a symmetric 3x3 (a00, a10, a11, a20, a21, a22) + damping I."""
    d0 = a[0] + damping
    if d0 <= 0.0:
        return None
    l00 = math.sqrt(d0)
    l10 = a[1] / l00
    d1 = a[2] + damping - l10 * l10
    if d1 <= 0.0:
        return None
    l11 = math.sqrt(d1)
    l20 = a[3] / l00
    l21 = (a[4] - l20 * l10) / l11
    d2 = a[5] + damping - l20 * l20 - l21 * l21
    if d2 <= 0.0:
        return None
    return (l00, l10, l11, l20, l21, math.sqrt(d2))


class NormalSolver:
    """Least-squares pseudo-inverse J+ = J^T (J J^T + d I)^-1 of a small J.

    J is given by columns, one m-vector per joint (m <= 4 task rows), of
    which the ``free`` ones are used. The m x m normal matrix is factored
    once (Cholesky); :meth:`apply` then costs a few dozen flops.

    Args:
        cols: J's columns, one sequence of m floats per joint.
        free: Indices of the columns (joints) to use.
        damping: d added to the diagonal (lambda^2). If the factor's smallest
            pivot (a singular value squared, roughly) falls below ``floor``,
            the factorisation is redone with ``floor`` added instead.
        floor: The damping used near singularities.
    """

    __slots__ = ("cols", "free", "low", "m")

    def __init__(
        self,
        cols: Sequence[Sequence[float]],
        free: Sequence[int],
        damping: float,
        floor: float,
    ) -> None:
        self.cols, self.free = cols, free
        m = self.m = len(cols[free[0]]) if free else 0
        gram = [[0.0] * m for _ in range(m)]
        for k in free:
            c = cols[k]
            for i in range(m):
                ci = c[i]
                row = gram[i]
                for j in range(i + 1):
                    row[j] += ci * c[j]
        low = _cholesky(gram, damping)
        if low is None or min(low[i][i] for i in range(m)) ** 2 < floor:
            low = _cholesky(gram, floor)
        self.low = low

    def apply(self, v: Sequence[float]) -> list[float]:
        """J+ v, one value per free joint (zeros if J has no rows)."""
        if self.low is None or not self.m:
            return [0.0] * len(self.free)
        y = _solve(self.low, v)
        cols = self.cols
        out = []
        for k in self.free:
            c, total = cols[k], 0.0
            for i in range(self.m):
                total += c[i] * y[i]
            out.append(total)
        return out

    def times(self, x: Sequence[float]) -> list[float]:
        """J x for x given over all joints (uses the free columns), m values."""
        out = [0.0] * self.m
        for k in self.free:
            xk = x[k]
            if xk:
                c = self.cols[k]
                for i in range(self.m):
                    out[i] += c[i] * xk
        return out


def _cholesky(gram: list[list[float]], damping: float) -> list[list[float]] | None:
    """Lower factor L of gram + damping I (lower triangle used), or None."""
    m = len(gram)
    low = [[0.0] * m for _ in range(m)]
    for i in range(m):
        for j in range(i + 1):
            s = gram[i][j] + (damping if i == j else 0.0)
            for k in range(j):
                s -= low[i][k] * low[j][k]
            if i == j:
                if s <= 0.0:
                    return None
                low[i][i] = math.sqrt(s)
            else:
                low[i][j] = s / low[j][j]
    return low


def _solve(low: list[list[float]], b: Sequence[float]) -> list[float]:
    """x with L L^T x = b."""
    m = len(low)
    y = [0.0] * m
    for i in range(m):
        s = b[i]
        for k in range(i):
            s -= low[i][k] * y[k]
        y[i] = s / low[i][i]
    for i in reversed(range(m)):
        s = y[i]
        for k in range(i + 1, m):
            s -= low[k][i] * y[k]
        y[i] = s / low[i][i]
    return y
