"""The path spline: through every point, C2, guaranteed bounds, inside the ranges."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.interpolate import CubicSpline
from test_timing_paths import touching_limits_path

from services.timing.knot_derivatives import knot_curvatures, knot_slopes
from services.timing.path_spline import PathSpline
from shared.robot import load_arm, motion_limits

LIMITS = motion_limits(load_arm("right").limits)
WIDE = np.full(3, 1e9)


def _random_spline(seed: int, k: int = 12) -> tuple[PathSpline, np.ndarray]:
    rng = np.random.default_rng(seed)
    points = rng.normal(size=(k, 3))
    return PathSpline(points, rng.uniform(0.2, 2.0, k - 1), -WIDE, WIDE), points


@pytest.mark.parametrize("k", [2, 3, 4, 7, 40])
def test_knot_derivatives_equal_scipys_not_a_knot_cubic_spline(k: int) -> None:
    """Slopes and curvatures agree with scipy.interpolate.CubicSpline."""
    rng = np.random.default_rng(k)
    widths = rng.uniform(0.1, 2.0, k - 1)
    values = rng.normal(size=(k, 4))
    knots = np.concatenate(([0.0], np.cumsum(widths)))
    reference = CubicSpline(knots, values)
    slopes = knot_slopes(values, widths)
    assert np.allclose(slopes, reference(knots, 1))
    assert np.allclose(knot_curvatures(values, widths, slopes), reference(knots, 2))


def test_the_spline_passes_through_every_point() -> None:
    """q(u_k) is path point k."""
    spline, points = _random_spline(0)
    assert np.allclose(spline.evaluate(spline.knots).position, points, atol=1e-12)


def test_value_slope_and_curvature_are_continuous_at_the_knots() -> None:
    """C2: both sides of an inner knot agree up to the second derivative."""
    spline, _ = _random_spline(1)
    eps = 1e-9
    left = spline.evaluate(spline.knots[1:-1] - eps)
    right = spline.evaluate(spline.knots[1:-1] + eps)
    for a, b in zip(left[:3], right[:3], strict=True):
        assert np.allclose(a, b, atol=1e-6)


def test_derivatives_match_finite_differences() -> None:
    """first, second, third agree with differences of the lower order."""
    spline, _ = _random_spline(2)
    u = np.linspace(0.0, spline.length, 20001)
    s = spline.evaluate(u)
    for lower, higher in ((s.position, s.first), (s.first, s.second)):
        fd = np.gradient(lower, u, axis=0)
        assert np.allclose(fd[2:-2], higher[2:-2], atol=1e-3 * np.abs(higher).max())


def test_bounds_hold_everywhere_and_are_not_loose() -> None:
    """Dense samples never exceed the bounds, which they nearly reach."""
    for seed in range(5):
        spline, _ = _random_spline(seed, 20)
        u = np.linspace(0.0, spline.length, 40001)
        s = spline.evaluate(u)
        for values, bound in zip(s[1:4], spline.bounds(), strict=True):
            per_piece = bound[s.piece]
            assert np.all(np.abs(values) <= per_piece + 1e-9)
            assert np.abs(values).max() > 0.85 * bound.max()


def test_joints_stopping_at_their_limits_never_overshoot() -> None:
    """Paths that run into the range's ends stay inside it on the whole curve."""
    rng = np.random.default_rng(3)
    for _ in range(40):
        path = touching_limits_path(rng, LIMITS)
        keep = np.concatenate(([True], np.abs(np.diff(path, axis=0)).max(1) > 1e-9))
        points = path[keep]
        widths = np.linalg.norm(np.diff(points, axis=0), axis=1)
        spline = PathSpline(points, widths, LIMITS.lower, LIMITS.upper)
        q = spline.evaluate(np.linspace(0.0, spline.length, 5000)).position
        assert np.all(q >= LIMITS.lower) and np.all(q <= LIMITS.upper)
        assert np.all(spline.control >= LIMITS.lower[None, None] - 1e-15)
