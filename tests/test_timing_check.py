"""check_limits and the boundary checks: each violation named, exactly."""

from __future__ import annotations

import numpy as np
import pytest

from services.timing import check_limits
from services.timing.check import check_times
from services.timing.finite_differences import divided_differences
from shared.errors import InvalidInputError, LimitViolationError
from shared.robot import load_arm, motion_limits

LIMITS = motion_limits(load_arm("right").limits)
MIDDLE = 0.5 * (LIMITS.lower + LIMITS.upper)


def _ramp(speed: float, joint: int = 0, n: int = 20, dt: float = 0.01):
    """Times and a constant-speed motion of one joint."""
    times = np.arange(n) * dt
    q = np.tile(MIDDLE, (n, 1))
    q[:, joint] += speed * times
    return times, q


def test_divided_differences_are_exact_for_a_cubic_on_an_uneven_grid() -> None:
    """For x = t^3 the estimates equal 3t^2, 6t, 6 somewhere in each window."""
    t = np.cumsum(np.random.default_rng(0).uniform(0.005, 0.02, 30))
    fd = divided_differences(t, (t**3)[:, None])
    assert np.allclose(fd.jerk, 6.0)
    for k, a in enumerate(fd.acceleration[:, 0]):
        assert 6 * t[k] <= a <= 6 * t[k + 2]


def test_a_trajectory_within_limits_passes() -> None:
    """A slow ramp passes silently."""
    check_limits(*_ramp(1.0), LIMITS)


def test_a_single_sample_passes() -> None:
    """One posture within range is a valid (still) trajectory."""
    check_limits([0.0], [MIDDLE], LIMITS)


def test_too_fast_names_joint_quantity_value_sample_and_time() -> None:
    """Speed above the limit: LimitViolationError with every field."""
    times, q = _ramp(10.0, joint=3, n=5)
    with pytest.raises(LimitViolationError) as caught:
        check_limits(times, q, LIMITS)
    error = caught.value
    assert (error.joint, error.quantity, error.index) == ("RElbowRoll", "velocity", 1)
    assert error.value == pytest.approx(10.0)
    assert error.limit == pytest.approx(7.19407)
    assert error.time == pytest.approx(0.01)
    assert error.message == (
        "RElbowRoll velocity 10 rad/s at sample 1 (t = 0.010 s) exceeds its limit "
        "7.194 rad/s"
    )


def test_an_acceleration_step_is_caught_at_its_sample() -> None:
    """A sudden change of speed: acceleration named at the kink's sample."""
    times, q = _ramp(0.0)
    q[10:, 1] += 3.0 * (times[10:] - times[10]) - 0.0  # starts moving at sample 10
    with pytest.raises(LimitViolationError) as caught:
        check_limits(times, q, LIMITS)
    assert caught.value.quantity == "acceleration"
    assert caught.value.joint == "RShoulderRoll"
    assert caught.value.index == 10


def test_jerk_is_checked() -> None:
    """Constant acceleration switched on at once: jerk names the joint."""
    times = np.arange(30) * 0.01
    q = np.tile(MIDDLE, (30, 1))
    ramp = np.clip(times - 0.1, 0.0, None)
    q[:, 0] += 0.5 * 20.0 * ramp**2  # 20 rad/s^2 from t = 0.1 s
    with pytest.raises(LimitViolationError) as caught:
        check_limits(times, q, LIMITS)
    assert (caught.value.quantity, caught.value.joint) == ("jerk", "RShoulderPitch")


def test_a_position_out_of_range_names_the_bound() -> None:
    """A posture beyond a range: quantity position, limit the bound crossed."""
    times, q = _ramp(0.0, n=5)
    q[2, 3] = LIMITS.lower[3] - 0.01
    with pytest.raises(LimitViolationError) as caught:
        check_limits(times, q, LIMITS)
    error = caught.value
    assert (error.quantity, error.index, error.joint) == ("position", 2, "RElbowRoll")
    assert error.limit == pytest.approx(LIMITS.lower[3])


@pytest.mark.parametrize(
    ("times", "message"),
    [
        ([0.0, 0.01, 0.01], r"sample 2 \(t = 0.01 s\) is not after sample 1"),
        ([0.0, np.nan, 0.02], "time at sample 1 is nan"),
        ([[0.0, 0.01]], "times must be a list"),
    ],
)
def test_bad_times_are_named(times: list[float], message: str) -> None:
    """Non-increasing, NaN or misshapen times: InvalidInputError naming the sample."""
    with pytest.raises(InvalidInputError, match=message):
        check_times(times)


def test_nan_positions_and_shape_mismatches_are_named() -> None:
    """NaN names sample and joint; a row count that differs from the times fails."""
    times, q = _ramp(0.0, n=4)
    q[1, 0] = np.inf
    with pytest.raises(InvalidInputError, match="RShoulderPitch at sample 1 is inf"):
        check_limits(times, q, LIMITS)
    with pytest.raises(InvalidInputError, match="positions has 3 rows but there are 4"):
        check_limits(times, q[:3], LIMITS)
