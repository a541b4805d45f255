"""The path parameter's Ruckig profile: evaluated in bulk exactly as Ruckig does."""

from __future__ import annotations

import numpy as np
import pytest
from ruckig import InputParameter, Ruckig, Trajectory

from services.timing.parameter_limits import ParameterLimits
from services.timing.scalar_profile import plan_rest_to_rest, scaled


def test_bulk_samples_equal_ruckigs_at_time() -> None:
    """position, velocity, acceleration at many times equal Trajectory.at_time."""
    limits = ParameterLimits(1.3, 4.0, 30.0)
    profile = plan_rest_to_rest(2.0, limits)
    inp = InputParameter(1)
    inp.current_position, inp.target_position = [0.0], [2.0]
    inp.max_velocity, inp.max_acceleration, inp.max_jerk = [1.3], [4.0], [30.0]
    trajectory = Trajectory(1)
    Ruckig(1).calculate(inp, trajectory)
    times = np.linspace(0.0, profile.duration, 157)
    got = profile.sample(times)
    for k, t in enumerate(times):
        p, v, a = (x[0] for x in trajectory.at_time(t))
        assert got.position[k] == pytest.approx(p, abs=1e-9)
        assert got.velocity[k] == pytest.approx(v, abs=1e-9)
        assert got.acceleration[k] == pytest.approx(a, abs=1e-9)


def test_scaled_limits_run_the_same_profile_slower() -> None:
    """Under scaled(limits, r) the profile is the original one r times slower."""
    limits = ParameterLimits(2.0, 8.0, 33.0)
    fast = plan_rest_to_rest(0.7, limits)
    slow = plan_rest_to_rest(0.7, scaled(limits, 1.7))
    assert slow.duration == pytest.approx(1.7 * fast.duration)
    tau = np.linspace(0.0, 1.0, 301)
    a, b = fast.sample(tau * fast.duration), slow.sample(tau * slow.duration)
    assert np.allclose(a.position, b.position, atol=1e-9)
    assert np.allclose(a.velocity, 1.7 * b.velocity, atol=1e-9)


def test_the_motion_starts_and_ends_at_rest() -> None:
    """Zero speed and acceleration at both ends, at the goal at the end."""
    profile = plan_rest_to_rest(0.7, ParameterLimits(2.0, 8.0, 33.0))
    end = profile.sample(np.array([0.0, profile.duration]))
    assert end.position.tolist() == pytest.approx([0.0, 0.7])
    assert end.velocity.tolist() == pytest.approx([0.0, 0.0], abs=1e-9)
    assert end.acceleration.tolist() == pytest.approx([0.0, 0.0], abs=1e-9)


def test_limits_are_kept() -> None:
    """|u_dot|, |u_ddot|, |u_dddot| within V, A, J at every sample."""
    profile = plan_rest_to_rest(3.0, ParameterLimits(1.0, 2.0, 5.0))
    s = profile.sample(np.linspace(0.0, profile.duration, 2000))
    assert np.all(np.abs(s.velocity) <= 1.0 + 1e-9)
    assert np.all(np.abs(s.acceleration) <= 2.0 + 1e-9)
    assert np.all(np.abs(s.jerk) <= 5.0 + 1e-9)
