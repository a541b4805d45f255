"""time_path: jerk-limited, on the path, at rest at the ends, typed errors."""

from __future__ import annotations

import numpy as np
import pytest
from test_timing_paths import (
    distance_to_polyline,
    random_smooth_path,
    touching_limits_path,
    wrists,
)

from services.timing import check_limits, time_path
from services.timing.finite_differences import divided_differences
from shared.errors import InvalidInputError, JointLimitError
from shared.robot import MotionLimits, load_arm, motion_limits

ARM = load_arm("right")
LIMITS = motion_limits(ARM.limits)


def _within_limits_by_hand(times: np.ndarray, q: np.ndarray, limits: MotionLimits):
    """Finite differences computed here, apart from check_limits (uniform grid)."""
    dt = times[1] - times[0]
    assert np.allclose(np.diff(times), dt)
    v = np.diff(q, axis=0) / dt
    a = np.diff(q, 2, axis=0) / dt**2
    j = np.diff(q, 3, axis=0) / dt**3
    slack = 1e-6
    assert np.all(q >= limits.lower - 1e-12) and np.all(q <= limits.upper + 1e-12)
    assert np.all(np.abs(v) <= limits.velocity * (1 + slack))
    assert np.all(np.abs(a) <= limits.acceleration * (1 + slack))
    assert np.all(np.abs(j) <= limits.jerk * (1 + slack))


def test_hundreds_of_random_paths_stay_within_every_limit() -> None:
    """300 random paths, fastest and human: positions, speed, acc., jerk by FD."""
    rng = np.random.default_rng(7)
    for k in range(300):
        path = (
            touching_limits_path(rng, LIMITS)
            if k % 4 == 0
            else random_smooth_path(rng, LIMITS)
        )
        duration = None if k % 2 else float(rng.uniform(0.4, 1.2))
        out = time_path(path, LIMITS, duration=duration)
        _within_limits_by_hand(out.times, out.positions, LIMITS)
        check_limits(out.times, out.positions, LIMITS)


def test_the_trajectory_starts_and_ends_at_rest_on_the_path_ends() -> None:
    """First and last samples are the path's ends, with zero speed and acc."""
    path = random_smooth_path(np.random.default_rng(3), LIMITS, 80)
    out = time_path(path, LIMITS)
    assert np.array_equal(out.positions[0], path[0])
    assert np.allclose(out.positions[-1], path[-1], atol=1e-12)
    for field in (out.velocities, out.accelerations):
        assert np.allclose(field[[0, -1]], 0.0, atol=1e-9)
    assert out.path_index[0] == 0.0 and out.path_index[-1] == len(path) - 1
    assert np.all(np.diff(out.path_index) >= 0.0)


def test_samples_are_on_a_uniform_grid_at_the_rate() -> None:
    """Times are k / rate, k = 0..m - 1, for the default and another rate."""
    path = random_smooth_path(np.random.default_rng(4), LIMITS, 50)
    for rate in (100.0, 25.0):
        out = time_path(path, LIMITS, rate=rate)
        assert np.allclose(out.times, np.arange(len(out.times)) / rate)


def test_reported_derivatives_match_finite_differences() -> None:
    """Velocities and accelerations agree with differences of the positions."""
    path = random_smooth_path(np.random.default_rng(5), LIMITS, 100)
    out = time_path(path, LIMITS, rate=1000.0)
    fd = divided_differences(out.times, out.positions)
    mid_v = 0.5 * (out.velocities[1:] + out.velocities[:-1])
    assert np.allclose(fd.velocity, mid_v, atol=1e-3 * LIMITS.velocity.max())
    assert np.allclose(
        fd.acceleration, out.accelerations[1:-1], atol=2e-3 * LIMITS.acceleration.max()
    )


def test_every_sample_lies_on_the_joint_path() -> None:
    """The wrist at every sample is within 1 mm of the input's wrist polyline.

    Paths sampled about as densely as an IK path (wrist steps of a few mm);
    with coarse samples the polyline itself leaves the curve through them.
    """
    rng = np.random.default_rng(11)
    for _ in range(25):
        path = random_smooth_path(rng, LIMITS, int(rng.integers(300, 500)))
        out = time_path(path, LIMITS, duration=0.8)
        gap = distance_to_polyline(wrists(ARM, out.positions), wrists(ARM, path))
        assert gap.max() < 1e-3


def test_human_pace_takes_the_wanted_duration_when_the_limits_allow() -> None:
    """A short, gentle path timed for 0.8 s takes 0.8 s (to the sample)."""
    path = np.linspace(ARM.limits.middle, ARM.limits.middle + 0.3, 40)
    out = time_path(path, LIMITS, duration=0.8)
    assert out.duration == pytest.approx(0.8, abs=0.011)


def test_human_speed_profile_is_a_bell() -> None:
    """On a straight joint path the speed rises once and falls once, like min jerk."""
    path = np.linspace(ARM.limits.middle, ARM.limits.middle + 0.3, 40)
    out = time_path(path, LIMITS, duration=0.8)
    speed = np.linalg.norm(out.velocities, axis=1)
    peak = int(np.argmax(speed))
    assert np.all(np.diff(speed[: peak + 1]) >= -1e-9)
    assert np.all(np.diff(speed[peak:]) <= 1e-9)
    tau = out.times / out.duration
    reference = 30 * tau**2 * (1 - tau) ** 2 * 0.3 * np.sqrt(5) / out.duration
    assert np.max(np.abs(speed - reference)) < 0.05 * reference.max()


def test_fastest_is_faster_than_human() -> None:
    """For any path, the fastest timing is no slower than the human one."""
    rng = np.random.default_rng(12)
    for _ in range(30):
        path = random_smooth_path(rng, LIMITS)
        fastest = time_path(path, LIMITS).duration
        assert fastest <= time_path(path, LIMITS, duration=0.6).duration
    gentle = np.linspace(ARM.limits.middle, ARM.limits.middle + 0.2, 30)
    assert (
        time_path(gentle, LIMITS).duration
        < time_path(gentle, LIMITS, duration=0.6).duration
    )


def test_repeated_points_are_skipped_and_two_points_suffice() -> None:
    """Repeats (a path that pauses) and a two-point path are timed fine."""
    a, b = ARM.limits.middle, ARM.limits.middle + 0.2
    out = time_path([a, a, b, b, b], LIMITS)
    assert np.allclose(out.positions[[0, -1]], [a, b])
    assert out.path_index[-1] == 4.0
    check_limits(out.times, out.positions, LIMITS)


def test_zero_length_path_is_refused_by_name() -> None:
    """All points equal: InvalidInputError saying so."""
    q = np.tile(ARM.limits.middle, (5, 1))
    with pytest.raises(InvalidInputError, match="zero length: all 5 points equal"):
        time_path(q, LIMITS)


def test_nan_names_the_point_and_joint() -> None:
    """NaN in the path names the path point and the joint."""
    q = np.tile(ARM.limits.middle, (5, 1))
    q[3, 2] = np.nan
    with pytest.raises(InvalidInputError, match="RElbowYaw at path point 3 is nan"):
        time_path(q, LIMITS)


@pytest.mark.parametrize(
    ("q", "message"),
    [
        (np.zeros((1, 5)), r"shape \(n, 5\) with n >= 2, got shape \(1, 5\)"),
        (np.zeros((4, 4)), r"got shape \(4, 4\)"),
        (np.zeros(5), r"got shape \(5,\)"),
        ([["a"] * 5] * 2, "rows of 5 numbers"),
    ],
)
def test_wrong_shapes_are_refused(q: object, message: str) -> None:
    """Wrong shapes give InvalidInputError with the shape."""
    with pytest.raises(InvalidInputError, match=message):
        time_path(q, LIMITS)  # type: ignore[arg-type]


def test_a_point_out_of_range_names_the_point() -> None:
    """A posture outside a joint's range: JointLimitError at that point."""
    q = np.tile(ARM.limits.middle, (4, 1))
    q[2, 0] = 3.0
    with pytest.raises(
        JointLimitError, match=r"RShoulderPitch = 3\.00000 rad at path point 2"
    ):
        time_path(q, LIMITS)


@pytest.mark.parametrize(
    ("duration", "rate"), [(0.0, 100.0), (np.nan, 100.0), (1.0, 0.0)]
)
def test_bad_duration_or_rate_is_refused(duration: float, rate: float) -> None:
    """Durations and rates must be positive numbers."""
    q = [ARM.limits.middle, ARM.limits.middle + 0.1]
    with pytest.raises(InvalidInputError, match="must be a positive number"):
        time_path(q, LIMITS, duration=duration, rate=rate)


def test_the_left_arm_is_timed_within_its_limits() -> None:
    """The left arm's mirrored ranges are respected too."""
    limits = motion_limits(load_arm("left").limits)
    rng = np.random.default_rng(13)
    for _ in range(20):
        out = time_path(touching_limits_path(rng, limits), limits, duration=0.7)
        check_limits(out.times, out.positions, limits)
