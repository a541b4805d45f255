"""Wrist-path mode: joint angles at exactly the given times, checked, not retimed."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.interpolate import (  # type: ignore[import-untyped]
    CubicHermiteSpline,
    CubicSpline,
)

from services.timing import time_given
from services.timing.check import check_limits
from shared.errors import InvalidInputError, LimitViolationError
from shared.robot import load_arm, motion_limits

LIMITS = motion_limits(load_arm("right").limits)
HOME = load_arm("right").limits.middle


def _minimum_jerk(times: np.ndarray, change: np.ndarray) -> np.ndarray:
    tau = (times - times[0]) / (times[-1] - times[0])
    return HOME + np.outer(tau**3 * (10 - 15 * tau + 6 * tau**2), change)


def test_times_and_positions_are_kept_exactly() -> None:
    """Uneven times come back unchanged, with the angles given."""
    times = np.cumsum(np.r_[0.0, np.random.default_rng(0).uniform(0.008, 0.012, 99)])
    q = _minimum_jerk(times, np.full(5, 0.3))
    out = time_given(times, q, LIMITS)
    assert np.array_equal(out.times, times)
    assert np.array_equal(out.positions, q)
    assert np.array_equal(out.path_index, np.arange(100))


def test_velocities_match_the_analytic_derivative() -> None:
    """Second-order differences give the minimum-jerk speed closely."""
    times = np.linspace(0.0, 1.0, 101)
    q = _minimum_jerk(times, np.full(5, 0.3))
    out = time_given(times, q, LIMITS)
    tau = times
    exact = np.outer(30 * tau**2 * (1 - tau) ** 2, np.full(5, 0.3))
    assert np.allclose(out.velocities, exact, atol=2e-3)


def test_too_fast_a_timing_is_refused_naming_the_sample() -> None:
    """A 1.5 rad move in 0.1 s: LimitViolationError with joint and sample."""
    times = np.linspace(0.0, 0.1, 11)
    q = _minimum_jerk(times, np.array([1.5, 0.0, 0.0, 0.0, 0.0]))
    with pytest.raises(LimitViolationError) as caught:
        time_given(times, q, LIMITS)
    assert caught.value.joint == "RShoulderPitch"
    assert 0 < caught.value.index < 11


def test_times_that_do_not_increase_are_refused() -> None:
    """Sample 2 at the time of sample 1: named."""
    q = np.tile(HOME, (3, 1))
    with pytest.raises(InvalidInputError, match=r"sample 2 .* is not after sample 1"):
        time_given([0.0, 0.1, 0.1], q, LIMITS)


def test_one_posture_per_time() -> None:
    """Different counts of times and postures are refused."""
    with pytest.raises(InvalidInputError, match="2 postures for 3 times"):
        time_given([0.0, 0.1, 0.2], np.tile(HOME, (2, 1)), LIMITS)


def test_a_single_sample_is_a_still_trajectory() -> None:
    """One time, one posture: zero speed."""
    out = time_given([0.5], [HOME], LIMITS)
    assert out.velocities.tolist() == [[0.0] * 5]


def _eased_then_steady(times: np.ndarray) -> np.ndarray:
    """0 -> 1 over ``times``: speed eased up over the first half, then steady."""
    u = np.minimum(2.0 * times / times[-1], 1.0)
    speed = 3 * u**2 - 2 * u**3
    s = np.concatenate(
        [[0.0], np.cumsum(0.5 * (speed[1:] + speed[:-1]) * np.diff(times))]
    )
    return s / s[-1]


@pytest.mark.parametrize("end", ["start", "end"])
def test_a_path_at_speed_at_either_end_is_refused(end: str) -> None:
    """0.5 rad in 1 s, eased at one end and at speed (0.67 rad/s) at the
    other: every sample inside keeps the limits, but leaving or stopping dead
    within one 10 ms step asks 67 rad/s^2; named with that end's sample."""
    times = np.linspace(0.0, 1.0, 101)
    s = _eased_then_steady(times)
    s = s if end == "end" else 1.0 - s[::-1]
    q = HOME + np.outer(s, np.array([0.0, 0.0, 0.5, 0.0, 0.0]))
    check_limits(times, q, LIMITS)  # within the limits inside the path
    with pytest.raises(
        LimitViolationError, match=f"the path must {end} at rest"
    ) as caught:
        time_given(times, q, LIMITS)
    assert caught.value.joint == "RElbowYaw"
    assert caught.value.quantity == "acceleration"
    assert caught.value.index == (0 if end == "start" else 100)


def test_a_path_at_rest_at_both_ends_is_timed_as_given() -> None:
    """The same move eased at both ends passes, and its speed ends at zero."""
    times = np.linspace(0.0, 1.0, 101)
    out = time_given(times, _minimum_jerk(times, np.full(5, 0.3)), LIMITS)
    assert np.abs(out.velocities[[0, -1]]).max() < 1e-3


def test_the_velocities_are_those_of_the_curve_through_the_positions() -> None:
    """On uneven times, the cubic Hermite curve through the positions and
    velocities (the robot bridge's) has one acceleration at every sample,
    coming and going (it is the C2 spline the velocities came from), and the
    path starts and ends at rest. (Finite differences on the uneven grid
    gave a curve whose acceleration jumped from piece to piece and first
    and last velocities of 1e-3 rad/s.)"""
    rng = np.random.default_rng(9)
    times = np.sort(np.r_[0.0, rng.uniform(0.0, 4.0, 60), 4.0])
    q = _minimum_jerk(times, np.array([0.4, -0.2, 0.3, 0.5, -0.6]))
    out = time_given(times, q, LIMITS)
    assert np.array_equal(out.velocities[[0, -1]], np.zeros((2, 5)))
    curve = CubicHermiteSpline(times, q, out.velocities)
    inner = times[1:-1]
    coming = curve(inner - 1e-9, 2)
    going = curve(inner + 1e-9, 2)
    scale = np.abs(out.accelerations).max()
    assert np.abs(going - coming).max() < 1e-5 * scale
    assert np.allclose(curve(times, 2), out.accelerations, atol=1e-6 * scale)


def _bumped(size: float) -> tuple[np.ndarray, np.ndarray]:
    """The minimum-jerk move at 100 Hz with RElbowYaw's sample 50 moved by ``size``."""
    times = np.linspace(0.0, 1.0, 101)
    q = _minimum_jerk(times, np.full(5, 0.3))
    q[50, 2] += size
    return times, q


def test_jerk_between_samples_is_checked_on_the_curve_the_robot_plays() -> None:
    """A 0.15 mrad bump at one sample: its divided differences read about
    0.7 times the jerk limit, so the samples pass, but the curve through
    them (the bridge's cubic Hermite curve, this spline) jerks at about 1.6
    times it on the pieces beside the bump. Refused, naming the joint, the
    value on the curve and the piece's first sample (it was accepted)."""
    times, q = _bumped(1.5e-4)
    check_limits(times, q, LIMITS)  # the samples alone pass
    with pytest.raises(LimitViolationError, match=r"between samples 4[89] and") as err:
        time_given(times, q, LIMITS)
    error = err.value
    assert (error.joint, error.quantity) == ("RElbowYaw", "jerk")
    assert error.index in (48, 49, 50)
    assert error.time == times[error.index]
    curve = CubicSpline(times, q, bc_type="clamped")  # what plays
    on_piece = abs(curve(times[error.index] + 0.005, 3)[2])
    assert error.value == pytest.approx(on_piece, rel=1e-6)
    assert error.value > 1.5 * LIMITS.jerk[2]


def test_an_accepted_path_keeps_the_jerk_limit_everywhere_between_samples() -> None:
    """A 0.05 mrad bump passes, and the bridge's curve through the returned
    positions and velocities stays within the jerk limit on every piece."""
    times, q = _bumped(5e-5)
    out = time_given(times, q, LIMITS)
    curve = CubicHermiteSpline(times, out.positions, out.velocities)
    middles = 0.5 * (times[1:] + times[:-1])
    assert (np.abs(curve(middles, 3)) <= LIMITS.jerk * (1 + 1e-9)).all()
