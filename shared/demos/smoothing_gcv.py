"""A smoothing spline's smoothing by generalised cross-validation, all at once.

scipy's ``make_smoothing_spline`` chooses its smoothing ``lam`` by
generalised cross-validation (GCV) when given none, but does not return it,
and finds it by a minimiser that calls a Python loop over the frames some
30 times: 60-300 ms for one coordinate of one gap's frames, which made a
file of 20 trials with 40 short gaps a marker import in 44 s instead of
1.3 s. ``gcv_fit`` finds the same criterion's minimum with numpy
alone, for several coordinates at once: the spline's fitted values are
``(I + lam K)^-1 y`` (Reinsch's form, Green & Silverman 1994, section 2.1,
the penalty scipy's ``lam`` weighs), so one eigendecomposition of ``K``
gives every ``lam``'s residual and trace in O(n): the same minimiser
(Brent's, over 0 to n) then finds the same ``lam`` (to 1e-7) for 1 ms.
The spline itself is the natural cubic spline through its fitted values
(ibid., theorem 2.4), so no spline need be fitted again.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from scipy.linalg import solve_banded  # type: ignore[import-untyped]
from scipy.optimize import minimize_scalar  # type: ignore[import-untyped]

from shared.demos.rotations import FloatArray


def _least_gcv(bend: FloatArray, spectrum: FloatArray) -> float:
    """The ``lam`` of least GCV for one column.

    Searched as ``make_smoothing_spline`` searches it (Brent's bounded
    method over 0 to n), which finds the same minimum where the criterion
    has several.

    Args:
        bend: K's eigenvalues, shape (n,).
        spectrum: The column in K's eigenvectors, shape (n,).
    """
    n = len(bend)

    def criterion(lam: float) -> float:
        scaled = lam * bend
        residual = float(((scaled / (1.0 + scaled)) ** 2) @ spectrum**2)
        return n * residual / (n - float(np.sum(1.0 / (1.0 + scaled)))) ** 2

    found = minimize_scalar(criterion, bounds=(0.0, n), method="bounded")
    return float(found.x)


def reinsch_matrix(times: FloatArray) -> FloatArray:
    """``K = Q R^-1 Q^T`` [1/s^3], shape (n, n), the splines' bending.

    ``y^T K y`` is the integral of the second derivative squared of the
    natural cubic spline through ``y`` at ``times`` [s], shape (n,),
    increasing, n >= 3.
    """
    h = np.diff(times)
    n = len(times)
    inner = np.arange(n - 2)
    q = np.zeros((n, n - 2))
    q[inner, inner] = 1.0 / h[:-1]
    q[inner + 1, inner] = -1.0 / h[:-1] - 1.0 / h[1:]
    q[inner + 2, inner] = 1.0 / h[1:]
    r = np.zeros((3, n - 2))
    r[0, 1:] = r[2, :-1] = h[1:-1] / 6.0
    r[1] = (h[:-1] + h[1:]) / 3.0
    return np.asarray(q @ solve_banded((1, 1), r, q.T))


class GcvFit(NamedTuple):
    """A smoothing spline's fit to samples, its smoothing chosen by GCV.

    Attributes:
        lam: Each column's smoothing, shape (m,): ``make_smoothing_spline``'s
            ``lam``.
        fitted: The spline's values at the samples' times, shape (n, m); the
            spline is the natural cubic spline through them.
    """

    lam: FloatArray
    fitted: FloatArray


def gcv_fit(times: FloatArray, values: FloatArray) -> GcvFit:
    """Each column's smoothing spline, its ``lam`` minimising the GCV criterion.

    The criterion is ``n RSS / (n - tr A)^2`` with ``A = (I + lam K)^-1``
    (Wahba 1990, ch. 4), the one ``make_smoothing_spline`` minimises.

    Args:
        times: Sample times [s], shape (n,), increasing, n >= 5.
        values: Samples, shape (n, m).
    """
    bend, basis = np.linalg.eigh(reinsch_matrix(times))
    bend = np.clip(bend, 0.0, None)
    spectrum = basis.T @ values
    lam = np.array(
        [_least_gcv(bend, spectrum[:, column]) for column in range(values.shape[1])]
    )
    fitted = basis @ (spectrum / (1.0 + np.outer(bend, lam)))
    return GcvFit(np.asarray(lam), np.asarray(fitted))
