"""Every frame against the limits, before anything is sent."""

from __future__ import annotations

import numpy as np
import pytest

from bridge.approach import approach_frames
from bridge.checked_frames import check_behavior, checked_frames
from bridge.checks import (
    check_accelerations,
    check_frames,
    check_jerks,
    check_speeds,
)
from bridge.choregraphe import QUANTUM
from bridge.frames import frame_velocities, frames_from_trajectory
from bridge.interpolation import positions_at
from bridge.limits import JERK_RAMP_TIME, RAMP_TIME, FrameLimits
from bridge.minimum_jerk import minimum_jerk_trajectory
from shared.errors import InvalidInputError, TrajectoryRefusedError
from shared.messages import CommandFrames, Trajectory
from shared.robot import Side, load_arm
from shared.robot.motion_limits import motion_limits
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
    target[3] = 1.5
    reach = minimum_jerk_trajectory("right", [start, target], [1.0])
    positions = np.asarray(reach.positions)
    positions[:, 3] += 0.1  # to 1.6: RElbowRoll's range ends at 1.54462 rad
    trajectory = reach.model_copy(update={"positions": positions.tolist()})
    with pytest.raises(
        TrajectoryRefusedError, match=r"RElbowRoll angle 1\.\d+ rad at frame \d+"
    ) as caught:
        check_frames(frames_from_trajectory(trajectory), FrameLimits.for_arm("right"))
    assert caught.value.quantity == "position" and caught.value.limit == pytest.approx(
        1.54462
    )


def test_an_absurd_angle_is_named_briefly() -> None:
    """1e308 rad reads as 1e+308, not as 309 digits."""
    limits = FrameLimits.for_arm("right")
    start = [float(v) for v in rest("right")]
    far = [1e308, *start[1:]]
    frames = CommandFrames(
        arm="right",
        rate=25.0,
        joint_names=list(limits.names),
        start=start,
        times=[0.04],
        positions=[far],
    )
    with pytest.raises(TrajectoryRefusedError) as caught:
        check_frames(frames, limits)
    assert "RShoulderPitch angle 1e+308 rad at frame 1" in caught.value.message
    assert len(caught.value.message) < 200


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


def frames_of(
    positions: np.ndarray, start: np.ndarray, rate: float = 100.0
) -> CommandFrames:
    """Right-arm frames 1..m at ``rate`` [Hz] from ``start``, positions (m, 5)."""
    return CommandFrames(
        arm=Side.RIGHT,
        rate=rate,
        joint_names=list(Side.RIGHT.joint_names),
        start=start.tolist(),
        times=(np.arange(1, len(positions) + 1) / rate).tolist(),
        positions=positions.tolist(),
    )


def test_the_jerk_of_a_cubic_is_measured_exactly() -> None:
    """Keys on q = q0 + c t^3 (any spacing) have jerk 6 c: a limit just above
    passes, one just below refuses at the first window, naming the jerk. (The
    frames' own windows: the cubic does not come to rest, which check_frames
    would also refuse.)"""
    start = rest("right")
    c = 40.0  # [rad/s^3] on RShoulderPitch: jerk 240 rad/s^3
    t = np.array([0.0, 0.01, 0.03, 0.04, 0.07, 0.08])
    q = np.tile(start, (len(t), 1))
    q[:, 0] += c * t**3
    limits = FrameLimits.for_arm("right")

    def check(jerk: float) -> None:
        within = limits._replace(jerk=np.full(5, jerk))
        check_jerks(
            check_accelerations(check_speeds(q, t, within), t, within), t, within
        )

    check(6.0 * c * (1 + 1e-6))
    with pytest.raises(TrajectoryRefusedError) as caught:
        check(6.0 * c * (1 - 1e-6))
    error = caught.value
    assert (error.joint, error.quantity, error.frame) == ("RShoulderPitch", "jerk", 2)
    assert error.value == pytest.approx(6.0 * c, rel=1e-6)
    assert "rad/s^3" in error.message and "frames 0 to 3" in error.message


def test_a_step_in_acceleration_is_refused_by_the_jerk_check() -> None:
    """Bang-bang RWristYaw (acceleration +-0.9 of its limit, switched at once):
    within the speed and acceleration checks, refused by the jerk check at the
    switch, against the default jerk limit (acceleration limit / 0.05 s)."""
    limits = FrameLimits.for_arm("right")
    start = rest("right")
    a, half, rate = 0.9 * limits.acceleration[4], 0.04, 100.0
    t = np.arange(1, round(2 * half * rate) + 1) / rate
    up = 0.5 * a * np.minimum(t, half) ** 2
    down = a * half * np.maximum(t - half, 0.0) - 0.5 * a * np.maximum(t - half, 0) ** 2
    positions = np.tile(start, (len(t), 1))
    positions[:, 4] += up + down
    frames = frames_of(positions, start, rate)
    q = np.vstack([start, positions])
    times = np.concatenate([[0.0], t])
    check_accelerations(check_speeds(q, times, limits), times, limits)  # pass
    with pytest.raises(TrajectoryRefusedError) as caught:
        check_frames(frames, limits)
    error = caught.value
    assert (error.joint, error.quantity) == ("RWristYaw", "jerk")
    assert abs(error.time - half) <= 2.0 / rate
    assert error.limit == pytest.approx(24.6229 / RAMP_TIME / JERK_RAMP_TIME)


@pytest.mark.parametrize(
    ("shape", "quantity", "frame"),
    [
        ("one frame", "acceleration", 0),
        ("ramp", "acceleration", 0),
        ("stop", "acceleration", 10),
    ],
)
def test_setting_off_or_stopping_abruptly_is_refused(
    shape: str, quantity: str, frame: int
) -> None:
    """The arm rests before frame 0 and after the last frame: a one-frame
    request moving RElbowYaw 0.2 rad (no acceleration window among its own
    frames), or setting off at a constant 7.5 rad/s, was played (every
    difference among the frames was within limits); so was a halt from 8
    rad/s. Each is refused, naming the joint, the rest and the frame."""
    start = rest("right")
    t = np.arange(1, 2 if shape == "one frame" else 11) / 25.0
    positions = np.tile(start, (len(t), 1))
    if shape == "one frame":
        positions[:, 2] -= 0.2
    elif shape == "ramp":
        positions[:, 2] -= 7.5 * t
    else:  # accelerating at 20 rad/s^2 to 8 rad/s at the last frame, then held
        positions[:, 2] -= 0.5 * 20.0 * t**2
    with pytest.raises(TrajectoryRefusedError) as caught:
        check_frames(frames_of(positions, start, 25.0), FrameLimits.for_arm("right"))
    error = caught.value
    assert (error.joint, error.quantity, error.frame) == ("RElbowYaw", quantity, frame)
    assert "the arm rests before the first frame and after the last" in error.message


def test_thousands_of_joint_names_are_not_all_quoted() -> None:
    """Frames of 3000 joints: the error names the first few and the count (it
    once quoted all 3000 names)."""
    names = [f"J{k}" for k in range(3000)]
    frames = CommandFrames(
        arm=Side.RIGHT,
        rate=25.0,
        joint_names=names,
        start=[0.0] * 3000,
        times=[0.04],
        positions=[[0.0] * 3000],
    )
    with pytest.raises(InvalidInputError) as caught:
        check_frames(frames, FrameLimits.for_arm("right"))
    assert caught.value.message.startswith(
        "frames move ['J0', 'J1', 'J2', 'J3', 'J4', 'J5', ...] (3000 joints), "
        "expected the joints ['RShoulderPitch',"
    )
    assert len(caught.value.message) < 300


def test_frames_of_another_arm_are_invalid(rng: np.random.Generator) -> None:
    """Left-arm frames checked against right-arm limits: InvalidInputError."""
    with pytest.raises(InvalidInputError, match="expected the joints"):
        check_frames(
            frames_from_trajectory(smooth(rng, "left")), FrameLimits.for_arm("right")
        )


def at_rest_around(frames: CommandFrames, count: int = 3) -> CommandFrames:
    """``frames`` with the arm held ``count`` frames at its start before them
    and at its end after them: what the robot does around the move."""
    period = 1.0 / frames.rate
    first = np.tile(frames.start, (count, 1))
    last = np.tile(frames.positions[-1], (count, 1))
    times = np.concatenate(
        [
            np.arange(1, count + 1) * period,
            np.asarray(frames.times) + count * period,
            frames.times[-1] + np.arange(count + 1, 2 * count + 1) * period,
        ]
    )
    return frames.model_copy(
        update={
            "times": times.tolist(),
            "positions": np.vstack([first, frames.positions, last]).tolist(),
        }
    )


@pytest.mark.parametrize(
    "target",
    [[-1.0, -1.0, -1.5, 1.4, 1.5], [1.45, 0.15, 1.25, 0.45, 0.2]],
    ids=["far", "near"],
)
@pytest.mark.parametrize("rate", [25.0, 1000.0])
def test_the_approach_move_stays_within_a_quarter_of_the_limits(
    target: list[float], rate: float
) -> None:
    """Far or near, the approach passes the checks at 25 % of the limits, jerk
    included, also seen with the arm at rest before and after it, at
    Choregraphe's 25 fps and at 1000 fps, where the frames show the motion
    itself: it starts and ends without a step in acceleration. (A half
    cosine's step passes at 25 fps but not at 1000.) Rounded to 32 bits as
    NAOqi holds them, the 1000 fps frames are a little rougher (a jerk of
    0.28 of the limit): within the limits, as the bridge checks them."""
    limits = FrameLimits.for_arm("right")
    current = rest("right")
    move = approach_frames(Side.RIGHT, current, np.array(target), limits, rate)
    quarter = limits._replace(
        velocity=0.25 * limits.velocity,
        acceleration=0.25 * limits.acceleration,
        jerk=0.25 * limits.jerk,
    )
    check_frames(at_rest_around(move), quarter, as_held=False)
    check_frames(at_rest_around(move), limits)
    assert np.allclose(move.positions[-1], target)
    assert move.duration >= 0.5


@pytest.mark.parametrize(
    ("given", "quantity"),
    [({"jerk": -1.0}, "jerk"), ({"acceleration": float("nan")}, "acceleration")],
)
def test_bridge_limits_given_by_hand_are_checked(
    given: dict[str, float], quantity: str
) -> None:
    """A negative or NaN limit is refused with the joint named, not trusted."""
    with pytest.raises(InvalidInputError, match=rf"{quantity} limit of RShoulderPitch"):
        FrameLimits.for_arm("right", **given)


def test_bridge_limits_are_the_timing_limits_loosened() -> None:
    """Same positions and speeds as the robot file; acceleration and jerk by
    the bridge's ramp times, above the timing service's defaults."""
    bridge = FrameLimits.for_arm("left")
    timing = motion_limits(load_arm("left").limits)
    np.testing.assert_array_equal(bridge.upper, timing.upper)
    np.testing.assert_array_equal(bridge.velocity, timing.velocity)
    np.testing.assert_allclose(bridge.acceleration, timing.velocity / RAMP_TIME)
    np.testing.assert_allclose(bridge.jerk, bridge.acceleration / JERK_RAMP_TIME)
    assert np.all(bridge.acceleration > timing.acceleration)
    assert np.all(bridge.jerk > timing.jerk)


def sparse_near_a_limit(speed: float = 0.05) -> Trajectory:
    """Three samples 1 s apart, RShoulderRoll coming within 1 mrad of its lower
    limit at t = 1 s still moving down at ``speed`` [rad/s] (the planned path
    turns back between samples): the cubic through them dips below the limit
    (0.1 degree at 0.05 rad/s, 1.1 at 0.2). The first sample is ``4 speed /
    3`` [rad] higher than the last, so that ``speed`` is the slope of the
    positions' own curve there (the clamped spline,
    ``bridge.velocity_agreement``): the velocities agree with the positions."""
    limits = load_arm("right").limits
    base = minimum_jerk_trajectory("right", [rest("right")] * 3, [1.0, 1.0])
    keep = [0, len(base.times) // 2, len(base.times) - 1]
    q = np.array([base.positions[k] for k in keep])
    v = np.zeros_like(q)
    q[:, 1] = limits.lower[1] + np.array([0.05 + 4.0 * speed / 3.0, 0.001, 0.05])
    v[1, 1] = -speed
    return base.model_copy(
        update={
            "times": [0.0, 1.0, 2.0],
            "positions": q.tolist(),
            "velocities": v.tolist(),
            "accelerations": np.zeros_like(q).tolist(),
            "primitives": ["x"] * 3,
            "wrist_path": [base.wrist_path[k] for k in keep],
        }
    )


def test_the_curve_between_sparse_samples_is_held_in_the_ranges() -> None:
    """The cubic overshoots the limit between samples the planner kept in
    range (refused at 1 Hz before); the frames are held inside, by the last
    written digit, and pass every check."""
    trajectory = sparse_near_a_limit()
    limits = FrameLimits.for_arm("right")
    t = np.linspace(0.0, 2.0, 201)
    assert positions_at(trajectory, t)[:, 1].min() < limits.lower[1]
    frames = checked_frames(trajectory, 25.0, limits)
    q = np.array(frames.positions)
    assert q[:, 1].min() >= limits.lower[1] + QUANTUM * (1 - 1e-9)
    check_behavior(frames, limits, frame_velocities(trajectory, frames))


def test_a_sample_out_of_range_is_named_as_a_sample() -> None:
    """Holding the curve in range must not hide a sample outside it."""
    trajectory = sparse_near_a_limit()
    q = np.array(trajectory.positions)
    q[1, 1] = load_arm("right").limits.lower[1] - 0.01
    bad = trajectory.model_copy(update={"positions": q.tolist()})
    with pytest.raises(
        TrajectoryRefusedError, match=r"RShoulderRoll angle -1\.3364 rad at sample 1 "
    ):
        checked_frames(bad, 25.0, FrameLimits.for_arm("right"))
