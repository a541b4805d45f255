"""Test paths for the timing tests: random smooth joint curves, and distances.

Helpers imported by the other ``test_timing_*`` files, with tests of their own.
"""

from __future__ import annotations

import numpy as np

from shared.robot import ArmModel, MotionLimits, load_arm, motion_limits


def random_smooth_path(
    rng: np.random.Generator, limits: MotionLimits, n: int | None = None
) -> np.ndarray:
    """A random smooth joint curve within the ranges, sampled at n points.

    Each joint is a sum of three sines squashed into 5-95 % of its range by
    tanh; samples are evenly spaced in the curve's parameter. Shape (n, 5).
    """
    n = int(rng.integers(2, 160)) if n is None else n
    s = np.linspace(0.0, 1.0, n)[:, None]
    amplitude = rng.uniform(0.2, 1.5, size=(3, 5))
    phase = rng.uniform(0.0, 2 * np.pi, size=(3, 5))
    wave = sum(
        amplitude[k] * np.sin((k + 1) * np.pi * s * rng.uniform(0.3, 1.0) + phase[k])
        for k in range(3)
    )
    middle = 0.5 * (limits.lower + limits.upper)
    half = 0.45 * (limits.upper - limits.lower)
    return middle + half * np.tanh(wave)


def touching_limits_path(rng: np.random.Generator, limits: MotionLimits) -> np.ndarray:
    """A random smooth path clipped to a narrower box, then moved onto the limits.

    Joints run into their range's ends and stay there for a while (as IK paths
    do when a joint stops at its limit): kinks exactly at the limits.
    """
    path = random_smooth_path(rng, limits, int(rng.integers(20, 120)))
    middle = 0.5 * (limits.lower + limits.upper)
    shrink = 0.9 * (path - middle)
    inner_lo, inner_hi = (
        middle + 0.5 * (limits.lower - middle),
        middle + 0.5 * (limits.upper - middle),
    )
    clipped = np.clip(middle + shrink, inner_lo, inner_hi)
    at_low, at_high = clipped <= inner_lo, clipped >= inner_hi
    return np.where(at_low, limits.lower, np.where(at_high, limits.upper, clipped))


def distance_to_polyline(points: np.ndarray, polyline: np.ndarray) -> np.ndarray:
    """Distance of each point (m, 3) to the polyline (k, 3) [m], shape (m,)."""
    if len(polyline) == 1:
        return np.linalg.norm(points - polyline[0], axis=1)
    a, b = polyline[:-1], polyline[1:]
    ab = b - a
    length2 = np.maximum(np.einsum("ij,ij->i", ab, ab), 1e-300)
    rel = points[:, None, :] - a[None, :, :]
    t = np.clip(np.einsum("mkj,kj->mk", rel, ab) / length2, 0.0, 1.0)
    nearest = a[None] + t[..., None] * ab[None]
    return np.linalg.norm(points[:, None, :] - nearest, axis=2).min(axis=1)


def wrists(arm: ArmModel, q: np.ndarray) -> np.ndarray:
    """Wrist positions [m] of postures q (m, 5), shape (m, 3)."""
    return np.array([arm.fk(row).wrist for row in q])


def test_random_paths_stay_inside_the_ranges() -> None:
    """The generator's paths lie strictly inside every joint's range."""
    limits = motion_limits(load_arm("right").limits)
    rng = np.random.default_rng(1)
    for _ in range(50):
        path = random_smooth_path(rng, limits)
        assert np.all(path > limits.lower) and np.all(path < limits.upper)


def test_touching_paths_reach_the_limits_exactly() -> None:
    """Some joints of the touching paths sit exactly at a limit."""
    limits = motion_limits(load_arm("right").limits)
    path = touching_limits_path(np.random.default_rng(2), limits)
    at = (path == limits.lower) | (path == limits.upper)
    assert at.any()
    assert np.all(path >= limits.lower) and np.all(path <= limits.upper)


def test_distance_to_polyline_matches_a_hand_computed_case() -> None:
    """A point above the middle of a segment is its height away from it."""
    line = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0]])
    points = np.array([[0.5, 0.0, 0.3], [2.0, 0.5, 0.0], [-1.0, 0.0, 0.0]])
    assert np.allclose(distance_to_polyline(points, line), [0.3, 1.0, 1.0])
