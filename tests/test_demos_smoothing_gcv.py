"""The smoothing found by GCV is scipy's, found without its slow search."""

from __future__ import annotations

import numpy as np
from scipy.interpolate import CubicSpline, make_smoothing_spline

from shared.demos.smoothing_gcv import gcv_fit, reinsch_matrix


def _noisy_reach() -> tuple[np.ndarray, np.ndarray]:
    """A reach's three coordinates [m] at 250 Hz, 1 mm noise, a 10-frame hole."""
    times = np.r_[np.arange(40), np.arange(50, 90)] / 250.0
    s = np.clip((times - 0.05) / 0.25, 0.0, 1.0)
    along = 0.4 * (10 * s**3 - 15 * s**4 + 6 * s**5)
    true = along[:, None] * np.array([1.0, 0.5, 0.2])
    return times, true + np.random.default_rng(3).normal(0.0, 0.001, true.shape)


def test_the_fit_is_scipys_gcv_smoothing_spline() -> None:
    """Each coordinate's spline (natural, through the fitted values) is the one
    make_smoothing_spline picks by GCV itself, within 1 um, in the hole too."""
    times, values = _noisy_reach()
    fit = gcv_fit(times, values)
    grid = np.linspace(times[0], times[-1], 500)
    ours = CubicSpline(times, fit.fitted, axis=0, bc_type="natural")(grid)
    for axis in range(3):
        scipys = make_smoothing_spline(times, values[:, axis])(grid)
        assert np.abs(ours[:, axis] - scipys).max() < 1e-6


def test_the_fitted_values_are_the_spline_with_that_smoothing() -> None:
    """The fitted values are make_smoothing_spline's at the returned lam."""
    times, values = _noisy_reach()
    fit = gcv_fit(times, values)
    for axis, lam in enumerate(fit.lam):
        spline = make_smoothing_spline(times, values[:, axis], lam=lam)
        assert np.allclose(spline(times), fit.fitted[:, axis], atol=1e-9)


def test_the_bending_matrix_measures_a_parabolas_bending() -> None:
    """y^T K y is the integral of y''^2: 4 over [0, 1] for y = t^2 (natural
    spline through t^2 bends less only near its ends), 0 for a line."""
    times = np.sort(np.random.default_rng(5).uniform(0.0, 1.0, 60))
    bending = reinsch_matrix(times)
    line = 2.0 * times - 1.0
    assert abs(line @ bending @ line) < 1e-6
    parabola = times**2
    assert 0.9 * 4 * (times[-1] - times[0]) < parabola @ bending @ parabola
    assert parabola @ bending @ parabola <= 4 * (times[-1] - times[0]) + 1e-6
