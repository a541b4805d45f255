"""Every frame against the limits, before anything is sent."""

from __future__ import annotations

import numpy as np
import pytest

from bridge.approach import approach_frames
from bridge.checks import check_frames
from bridge.frames import frames_from_trajectory
from bridge.limits import RAMP_TIME, FrameLimits
from bridge.minimum_jerk import minimum_jerk_trajectory
from shared.errors import InvalidInputError, TrajectoryRefusedError
from shared.messages import Trajectory
from shared.robot import Side, load_arm
from shared.robot.postures import rest


def smooth(rng: np.random.Generator, side: str = "right") -> Trajectory:
    limits = load_arm(side).limits
    targets = rng.uniform(
        limits.lower + 0.1 * limits.span, limits.upper - 0.1 * limits.span, (3, 5)
    )
    return minimum_jerk_trajectory(
        side, [rest(side), *targets, rest(side)], [1.0, 0.8, 0.9, 1.0]
    )


def with_sample(
    trajectory: Trajectory, index: int, joint: int, offset: float
) -> Trajectory:
    """``trajectory`` with one sample's joint moved by ``offset`` [rad]."""
    positions = np.asarray(trajectory.positions)
    positions[index, joint] += offset
    return trajectory.model_copy(update={"positions": positions.tolist()})


@pytest.mark.parametrize("side", ["right", "left"])
def test_smooth_trajectories_within_the_limits_pass(
    side: str, rng: np.random.Generator
) -> None:
    """Seeded minimum-jerk moves inside the ranges pass every check."""
    limits = FrameLimits.for_arm(side)
    for _ in range(20):
        check_frames(frames_from_trajectory(smooth(rng, side)), limits)


def test_one_frame_over_the_speed_limit_refuses_the_whole_trajectory(
    rng: np.random.Generator,
) -> None:
    """A 0.4 rad jump of RElbowYaw at frame 12 (t = 0.48 s, sample 48) is named
    with the joint, both frames, their times and the limit."""
    bad = with_sample(smooth(rng), 48, 2, 0.4)
    with pytest.raises(TrajectoryRefusedError) as caught:
        check_frames(frames_from_trajectory(bad), FrameLimits.for_arm("right"))
    error = caught.value
    assert (error.joint, error.quantity, error.frame) == ("RElbowYaw", "velocity", 12)
    assert error.time == pytest.approx(0.48)
    assert error.limit == pytest.approx(8.26797)
    assert error.message == (
        "trajectory refused, nothing was sent: RElbowYaw speed "
        f"{error.value:.3f} rad/s from frame 11 (t = 0.440 s) to frame 12 "
        "(t = 0.480 s) exceeds its limit 8.268 rad/s"
    )


def test_a_frame_out_of_range_is_named() -> None:
    """An angle beyond its range names the joint, the frame and the range."""
    start = rest("right")
    target = start.copy()
    target[3] = 1.6  # RElbowRoll's range ends at 1.54462 rad
    trajectory = minimum_jerk_trajectory("right", [start, target], [1.0])
    with pytest.raises(
        TrajectoryRefusedError, match=r"RElbowRoll angle 1\.\d+ rad at frame \d+"
    ) as caught:
        check_frames(frames_from_trajectory(trajectory), FrameLimits.for_arm("right"))
    assert caught.value.quantity == "position" and caught.value.limit == pytest.approx(
        1.54462
    )


def test_an_acceleration_spike_is_refused(rng: np.random.Generator) -> None:
    """Under the speed limit but a sharp kink: the acceleration check names it."""
    bad = with_sample(smooth(rng), 48, 4, 0.25)  # WristYaw, limit 24.6 rad/s
    limits = FrameLimits.for_arm("right")
    with pytest.raises(TrajectoryRefusedError) as caught:
        check_frames(frames_from_trajectory(bad), limits)
    error = caught.value
    assert (error.joint, error.quantity) == ("RWristYaw", "acceleration")
    assert error.frame in (11, 12, 13)
    assert error.limit == pytest.approx(24.6229 / RAMP_TIME)
    assert "rad/s^2" in error.message


def test_frames_of_another_arm_are_invalid(rng: np.random.Generator) -> None:
    """Left-arm frames checked against right-arm limits: InvalidInputError."""
    with pytest.raises(InvalidInputError, match="expected the joints"):
        check_frames(
            frames_from_trajectory(smooth(rng, "left")), FrameLimits.for_arm("right")
        )


def test_the_approach_move_stays_within_a_quarter_of_the_limits() -> None:
    """A far approach is slow: its frames pass the checks at 25 % of the limits."""
    limits = FrameLimits.for_arm("right")
    current = rest("right")
    target = np.array([-1.0, -1.0, -1.5, 1.4, 1.5])
    move = approach_frames(Side.RIGHT, current, target, limits, 25.0)
    quarter = limits._replace(
        velocity=0.25 * limits.velocity, acceleration=0.25 * limits.acceleration
    )
    check_frames(move, quarter)
    assert np.allclose(move.positions[-1], target)
    assert move.duration >= 0.5
