"""Frames that follow their trajectory (bridge.fidelity, bridge.checked_frames).

The straight lines between frames stray from a smooth curve by at most an
eighth of its largest acceleration times the frame period squared, and by a
quarter as much at twice the rate; a rate too low for a movement is refused
naming the joint, and the rate the refusal suggests passes every check.
"""

from __future__ import annotations

import math
import re

import numpy as np
import pytest
from test_bridge_checks import sparse_near_a_limit

from bridge.checked_frames import checked_frames
from bridge.fidelity import (
    FOLLOW_TOLERANCE,
    follow_tolerance,
    largest_gap,
)
from bridge.frames import frames_from_trajectory
from bridge.interpolation import positions_at
from bridge.limits import FrameLimits
from bridge.minimum_jerk import minimum_jerk_trajectory
from shared.errors import TrajectoryRefusedError
from shared.messages import Trajectory
from shared.robot import load_arm
from shared.robot.postures import forward, rest

LIMITS = FrameLimits.for_arm("right")


def reach(seconds: float = 1.0) -> Trajectory:
    """Rest to the arm stretched forward, minimum jerk, at 1000 Hz samples."""
    return minimum_jerk_trajectory(
        "right", [rest("right"), forward("right")], [seconds], rate=1000.0
    )


def wave(
    rng: np.random.Generator, swings: int = 4, amplitude: float = 0.4
) -> Trajectory:
    """From rest, RElbowYaw swings ``amplitude`` [rad] back and forth, 0.3 s a
    swing (over 1.32 rad it is faster than RElbowYaw's speed limit)."""
    start = rest("right")
    out = start.copy()
    out[2] += amplitude
    postures = [start, *([out, start] * (swings // 2))]
    jitter = rng.uniform(-0.02, 0.02, (len(postures), 5))
    jitter[0] = 0.0
    return minimum_jerk_trajectory(
        "right", np.asarray(postures) + jitter, [0.3] * (len(postures) - 1)
    )


@pytest.mark.parametrize("rate", [10.0, 25.0, 50.0])
def test_the_gap_keeps_the_chord_bound(rate: float) -> None:
    """gap <= max|q''| T^2 / 8 (the chord of a curve over one period T), and
    more than half of it: the check measures what the robot would skip."""
    trajectory = reach()
    gap = largest_gap(frames_from_trajectory(trajectory, rate), trajectory)[0]
    bound = np.abs(trajectory.accelerations).max() / (8.0 * rate**2)
    assert 0.5 * bound < gap <= bound * (1.0 + 1e-6)


def test_the_gap_falls_with_the_square_of_the_period() -> None:
    """Twice the rate, a quarter of the gap (within 10 %)."""
    trajectory = reach()
    gaps = [
        largest_gap(frames_from_trajectory(trajectory, r), trajectory)[0]
        for r in (20.0, 40.0)
    ]
    assert gaps[0] / gaps[1] == pytest.approx(4.0, rel=0.1)


def test_planned_speed_frames_at_25_hz_pass(rng: np.random.Generator) -> None:
    """Choregraphe's 25 Hz follows a reach and a wave within a degree."""
    for trajectory in (reach(), wave(rng)):
        frames = checked_frames(trajectory, 25.0, LIMITS)
        assert largest_gap(frames, trajectory)[0] < FOLLOW_TOLERANCE


def test_a_wave_at_2_hz_is_refused_and_the_suggested_rate_passes(
    rng: np.random.Generator,
) -> None:
    """At 2 Hz the swings fall between frames: refused (every limit check
    passes: they run first), naming RElbowYaw; the rate the message offers
    passes."""
    trajectory = wave(rng)
    with pytest.raises(TrajectoryRefusedError) as caught:
        checked_frames(trajectory, 2.0, LIMITS)
    error = caught.value
    print("\n" + error.message)
    assert error.quantity == "frame_rate" and error.joint == "RElbowYaw"
    assert error.value > FOLLOW_TOLERANCE == error.limit
    assert f"would pass {math.degrees(error.value):.1f} deg" in error.message
    offered = re.search(r"at (\d+) Hz it would not", error.message)
    assert offered is not None
    checked_frames(trajectory, float(offered[1]), LIMITS)


def test_checked_frames_refuses_a_rate_too_low_for_the_movement(
    rng: np.random.Generator,
) -> None:
    """The one entry the bridge, export and demo use applies the check."""
    with pytest.raises(TrajectoryRefusedError, match="between frames at 4 Hz"):
        checked_frames(wave(rng), 4.0, LIMITS)


def test_a_joint_within_its_acceleration_limit_passes_at_25_fps() -> None:
    """WristYaw may stray a T^2 / 8 between 25 fps frames at its bridge
    acceleration limit a (2.8 degrees, over the other joints' 1 degree): a
    quick turn within its limits strays more than a degree and passes, as
    the planner's fastest reaches with a palm must (1.0-1.1 degree there was
    once refused); at half the frame rate it is refused."""
    tolerance = follow_tolerance(LIMITS)
    assert tolerance[:4] == pytest.approx(FOLLOW_TOLERANCE)
    wrist = LIMITS.acceleration[4]
    assert tolerance[4] == pytest.approx(wrist / (8.0 * 25.0**2))
    start, turned = rest("right"), rest("right")
    start[4], turned[4] = 0.9, -0.9
    # minimum jerk over T: peak jerk 60 A / T^3, taken to 80 % of the limit
    quick = (60.0 * 1.8 / (0.8 * LIMITS.jerk[4])) ** (1.0 / 3.0)
    trajectory = minimum_jerk_trajectory("right", [start, turned], [quick], rate=1000.0)
    frames = frames_from_trajectory(trajectory, 25.0)
    assert FOLLOW_TOLERANCE < largest_gap(frames, trajectory)[0] <= tolerance[4]
    checked_frames(trajectory, 25.0, LIMITS)
    with pytest.raises(TrajectoryRefusedError, match="RWristYaw would pass"):
        checked_frames(trajectory, 12.5, LIMITS)


def test_a_curve_over_a_limit_is_followed_as_the_frames_hold_it() -> None:
    """Between samples 1 s apart the cubic dips 1.1 degree below
    RShoulderRoll's lower limit, where the frames are held in the range: no
    frame rate follows that dip. It was refused at 5 and 25 Hz ("raise the
    frame rate") while 4 Hz passed; the lines are now compared with the
    curve held in the range, the one the frames come from."""
    trajectory = sparse_near_a_limit(speed=0.2)
    t = np.linspace(0.0, 2.0, 2001)
    dip = LIMITS.lower[1] - positions_at(trajectory, t)[:, 1].min()
    assert dip > FOLLOW_TOLERANCE
    passed = [checked_frames(trajectory, rate, LIMITS) for rate in (4.0, 5.0, 25.0)]
    inside = (LIMITS.lower, LIMITS.upper)
    for frames in passed:
        assert largest_gap(frames, trajectory, inside)[0] < FOLLOW_TOLERANCE


def test_a_rate_is_offered_only_if_its_frames_pass_every_check(
    rng: np.random.Generator,
) -> None:
    """Swings of 1.4 rad in 0.3 s (8.75 rad/s, over RElbowYaw's 8.27) keep
    every limit in frames 0.5 s apart, which cut them short: refused at 2 Hz.
    The rate once offered there was refused in turn for that speed; now no
    rate is offered and the refusal says what breaks at the rate tried."""
    trajectory = wave(rng, amplitude=-1.4)
    with pytest.raises(TrajectoryRefusedError) as caught:
        checked_frames(trajectory, 2.0, LIMITS)
    error = caught.value
    print("\n" + error.message)
    assert error.quantity == "frame_rate" and "it would not" not in error.message
    tried = re.search(
        r"no frame rate is offered: at (\d+) Hz RElbowYaw speed", error.message
    )
    assert tried is not None
    with pytest.raises(TrajectoryRefusedError, match="RElbowYaw speed"):
        checked_frames(trajectory, float(tried[1]), LIMITS)


@pytest.mark.parametrize("rate", [1.0, 2.0, 4.0])
def test_every_rate_offered_passes_every_check(
    rng: np.random.Generator, rate: float
) -> None:
    """Waves of 0.2 to 1.6 rad and sparse samples dipping past a limit, at
    rates too low for them: whenever a refusal offers a rate, frames at that
    rate pass every check the bridge makes."""
    trajectories = [wave(rng, amplitude=a) for a in np.linspace(-1.6, -0.2, 8)]
    trajectories += [sparse_near_a_limit(speed) for speed in (0.05, 0.2, 0.5, 1.0)]
    offered = 0
    for trajectory in trajectories:
        try:
            checked_frames(trajectory, rate, LIMITS)
            continue
        except TrajectoryRefusedError as error:
            found = re.search(r"at (\d+) Hz it would not", error.message)
        if found is not None:
            checked_frames(trajectory, float(found[1]), LIMITS)
            offered += 1
    assert offered >= 4


def test_a_curve_resting_at_every_frame_is_compared_at_the_quarters() -> None:
    """Samples 1 s apart, the arm at rest at each (zero speeds), sent at 1 fps:
    frames fall on the samples, and the curve between them crosses the
    straight line at its midpoint, where alone it was compared (8.6 degrees
    passed as 0 in a 64-target task). At the quarter points the cubic is
    3/32 of the step off the line: 2.7 degrees for a 0.5 rad step."""
    q0 = np.array(rest("right"))
    q1 = q0 + np.array([-0.5, 0.0, 0.0, 0.0, 0.0])
    zeros = [[0.0] * 5] * 3
    trajectory = Trajectory(
        arm="right",
        joint_names=list(load_arm("right").joint_names),
        times=[0.0, 1.0, 2.0],
        positions=[q0.tolist(), q1.tolist(), q0.tolist()],
        velocities=zeros,
        accelerations=zeros,
        primitives=["least-norm"] * 3,
        wrist_path=[(0.0, 0.0, 0.0)] * 3,
        method="least-norm",
    )
    quarter = positions_at(trajectory, np.array([0.25]))[0]
    line = q0 + 0.25 * (q1 - q0)
    assert math.degrees(abs(quarter[0] - line[0])) == pytest.approx(
        math.degrees(0.5 * 3 / 32), rel=1e-6
    )
    with pytest.raises(
        TrajectoryRefusedError, match=r"RShoulderPitch would pass 2\.7 deg"
    ):
        checked_frames(trajectory, 1.0, FrameLimits.for_arm("right"))
