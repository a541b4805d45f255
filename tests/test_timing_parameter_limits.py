"""Limits on the path parameter: sufficient for every joint, and short."""

from __future__ import annotations

import numpy as np
import pytest
from ruckig import InputParameter, Ruckig, Trajectory
from test_timing_paths import random_smooth_path

from services.timing.parameter_limits import (
    ParameterLimits,
    parameter_limits,
    rest_to_rest_time,
)
from services.timing.path_spline import PathSpline
from services.timing.time_path import knot_widths
from shared.robot import load_arm, motion_limits

LIMITS = motion_limits(load_arm("right").limits)


def _ruckig_duration(length: float, v: float, a: float, j: float) -> float:
    inp = InputParameter(1)
    inp.current_position, inp.target_position = [0.0], [length]
    inp.max_velocity, inp.max_acceleration, inp.max_jerk = [v], [a], [j]
    trajectory = Trajectory(1)
    Ruckig(1).calculate(inp, trajectory)
    return float(trajectory.duration)


def test_closed_form_time_equals_ruckigs_duration() -> None:
    """rest_to_rest_time agrees with Ruckig on random limits and lengths."""
    rng = np.random.default_rng(0)
    for _ in range(200):
        length, v, a, j = (
            rng.uniform(0.01, 3.0),
            *rng.uniform(0.1, 10.0, 2),
            rng.uniform(1, 500),
        )
        expected = _ruckig_duration(length, v, a, j)
        got = rest_to_rest_time(length, np.array([v]), np.array([a]), np.array([j]))[0]
        assert got == pytest.approx(expected, rel=1e-9, abs=1e-9)


def test_derived_limits_satisfy_the_chain_rule_bounds_on_every_piece() -> None:
    """M1 V <= v, M2 V^2 + M1 A <= a, M3 V^3 + 3 M2 V A + M1 J <= j."""
    rng = np.random.default_rng(1)
    for _ in range(50):
        path = random_smooth_path(rng, LIMITS, 60)
        spline = PathSpline(
            path, knot_widths(path, None, LIMITS), LIMITS.lower, LIMITS.upper
        )
        b = spline.bounds()
        v, a, j = parameter_limits(b, LIMITS, spline.length)
        assert np.all(b.first * v <= LIMITS.velocity * (1 + 1e-12))
        assert np.all(
            b.second * v**2 + b.first * a <= LIMITS.acceleration * (1 + 1e-12)
        )
        jerk = b.third * v**3 + 3 * b.second * v * a + b.first * j
        assert np.all(jerk <= LIMITS.jerk * (1 + 1e-12))


def test_caps_are_respected() -> None:
    """With caps, V, A and J never exceed them."""
    path = random_smooth_path(np.random.default_rng(2), LIMITS, 60)
    spline = PathSpline(
        path, knot_widths(path, None, LIMITS), LIMITS.lower, LIMITS.upper
    )
    caps = ParameterLimits(0.01, 0.02, 0.03)
    got = parameter_limits(spline.bounds(), LIMITS, spline.length, caps)
    assert got.velocity <= 0.01 and got.acceleration <= 0.02 and got.jerk <= 0.03
