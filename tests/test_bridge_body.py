"""The bridge sends nothing that would bring the arm into NAO's own body.

Against the simulated NAO over real libqi, in this process: a trajectory
that passes through the torso, and an approach to a start whose straight
way from where the arm is passes through it, are refused, and the sim's log
shows nothing more reached it; the same start approached from rest plays.
Both ends of each are clear of the body, and the way between them is not
(checked here with the body model, so the postures keep their meaning).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from bridge.checked_frames import checked_frames
from bridge.limits import FrameLimits
from bridge.minimum_jerk import minimum_jerk_trajectory
from bridge.naoqi_client import NaoqiClient
from bridge.robot_bridge import RobotBridge
from bridge.sim import SimProcess
from bridge.sim.log import read_log
from shared.errors import InvalidInputError, TrajectoryRefusedError
from shared.robot import load_arm
from shared.robot.body import MARGIN, arm_points, clearances
from shared.robot.other_arm import with_other_arm
from shared.robot.postures import rest

#: Two postures clear of the body whose straight way in joint space is not:
#: the hand comes back through the torso between them. Each is reached from
#: rest along a clear way.
AWAY = np.array([-0.27, 0.14, 1.5, 1.49, 1.53])
ACROSS = np.array([-0.4, 0.16, -0.46, 1.3, 0.92])


def least_clearance(start: np.ndarray, end: np.ndarray) -> np.ndarray:
    """Each posture's clearance along the straight way [m], (81,)."""
    way = start + np.linspace(0.0, 1.0, 81)[:, None] * (end - start)
    return clearances(arm_points(load_arm("right"), way)).min(axis=(1, 2))


def calls(sim: SimProcess) -> int:
    """How many angleInterpolation calls the sim took."""
    assert sim.log_path is not None
    return sum(
        1
        for e in read_log(Path(sim.log_path))
        if e["event"] == "call" and e["method"] == "angleInterpolation"
    )


def test_the_postures_are_clear_and_the_way_between_them_is_not() -> None:
    way = least_clearance(AWAY, ACROSS)
    assert way[0] > MARGIN and way[-1] > MARGIN
    assert way.min() < 0
    assert least_clearance(rest("right"), AWAY).min() > MARGIN
    assert least_clearance(rest("right"), ACROSS).min() > MARGIN


@pytest.fixture
def bridge(sim: SimProcess) -> RobotBridge:
    """A bridge whose arm holds ``AWAY`` (reached by an approach from rest)."""
    robot = RobotBridge(NaoqiClient(sim.url))
    robot.execute(minimum_jerk_trajectory("right", [AWAY, AWAY], [0.5]))
    return robot


def test_a_trajectory_through_the_torso_is_refused_and_nothing_is_sent(
    sim: SimProcess, bridge: RobotBridge
) -> None:
    before = calls(sim)
    through = minimum_jerk_trajectory("right", [AWAY, ACROSS], [2.0])
    with pytest.raises(TrajectoryRefusedError, match=r"NAO's \w+ at sample") as err:
        bridge.execute(through, rate=50.0)
    refusal = err.value
    assert refusal.quantity == "clearance"
    assert refusal.joint == "right hand"  # first by the head, then into the torso
    assert refusal.value < refusal.limit == MARGIN
    assert str(refusal).startswith("trajectory refused, nothing was sent")
    assert calls(sim) == before
    # the sample named is the first too near: the one before it keeps clear
    q = np.array(through.positions)
    gaps = clearances(arm_points(load_arm("right"), q)).min(axis=(1, 2))
    assert gaps[refusal.frame] < MARGIN <= gaps[refusal.frame - 1]
    assert refusal.time == pytest.approx(through.times[refusal.frame])


def test_frames_between_two_clear_samples_are_checked() -> None:
    """A trajectory of its two ends alone (2 s apart), both clear: the
    frames the robot would be sent between them pass the head and cross
    the torso, and are refused by frame."""
    ends = minimum_jerk_trajectory("right", [AWAY, ACROSS], [2.0], rate=0.5)
    assert len(ends.times) == 2
    with pytest.raises(TrajectoryRefusedError, match=r"at frame \d+ \(t = ") as err:
        checked_frames(ends, 50.0, FrameLimits.for_arm("right"))
    assert err.value.quantity == "clearance"
    assert 0 < err.value.time < 2.0


def test_a_refusal_counts_time_from_the_trajectorys_start() -> None:
    """The same trajectory 5 s later on its clock: the same sample and time."""
    through = minimum_jerk_trajectory("right", [AWAY, ACROSS], [2.0])
    later = through.model_copy(update={"times": [t + 5.0 for t in through.times]})
    limits = FrameLimits.for_arm("right")
    refusals = []
    for trajectory in (through, later):
        with pytest.raises(TrajectoryRefusedError) as err:
            checked_frames(trajectory, 50.0, limits)
        refusals.append((err.value.frame, err.value.time))
    assert refusals[0] == pytest.approx(refusals[1])
    assert refusals[0][1] < 2.0


def test_frames_written_for_choregraphe_are_checked_the_same() -> None:
    through = minimum_jerk_trajectory("right", [AWAY, ACROSS], [2.0])
    with pytest.raises(TrajectoryRefusedError, match="clear of the torso"):
        checked_frames(through, 25.0, FrameLimits.for_arm("right"), behavior=True)


def test_an_approach_through_the_torso_is_refused_and_from_rest_it_plays(
    sim: SimProcess, bridge: RobotBridge
) -> None:
    """The arm holds AWAY; a hold at ACROSS needs an approach from there,
    straight through the torso: refused before anything moves. Back at
    rest, the approach to ACROSS is clear, and the hold plays."""
    hold = minimum_jerk_trajectory("right", [ACROSS, ACROSS], [0.5])
    before = calls(sim)
    with pytest.raises(TrajectoryRefusedError, match="at approach frame") as err:
        bridge.execute(hold, rate=50.0)
    assert err.value.quantity == "clearance"
    assert "(in the approach move from where the arm is)" in str(err.value)
    assert calls(sim) == before
    bridge.execute(minimum_jerk_trajectory("right", [rest("right")] * 2, [0.5]))
    reply = bridge.execute(hold, rate=50.0)
    assert reply.approach_duration > 0
    assert calls(sim) == before + 4  # to rest and its hold, to ACROSS and its hold


#: A right-arm way in front of the chest, clear of NAO's body and of the
#: left arm hanging at rest, and a left-arm posture that lies across it.
SWEEP_FROM = np.array([-0.64, -0.43, 1.85, 0.32, 1.04])
SWEEP_TO = np.array([0.31, 0.03, -0.56, 1.42, -0.16])
LEFT_ACROSS = np.array([0.54, -0.09, -0.56, -1.05, -1.54])


def test_a_trajectory_through_the_other_arm_is_refused_where_that_arm_is(
    sim: SimProcess,
) -> None:
    """The left arm held across the right arm's way: the right arm's
    trajectory is refused naming the left arm's part, nothing sent; with
    the left arm back at rest the same trajectory plays."""
    robot = RobotBridge(NaoqiClient(sim.url))
    robot.execute(minimum_jerk_trajectory("left", [LEFT_ACROSS] * 2, [0.5]))
    robot.execute(minimum_jerk_trajectory("right", [SWEEP_FROM] * 2, [0.5]))
    sweep = minimum_jerk_trajectory("right", [SWEEP_FROM, SWEEP_TO], [2.0])
    before = calls(sim)
    with pytest.raises(TrajectoryRefusedError, match=r"NAO's left \w+") as err:
        robot.execute(sweep, rate=50.0)
    assert err.value.quantity == "clearance"
    assert str(err.value).startswith("trajectory refused, nothing was sent")
    assert calls(sim) == before
    robot.execute(minimum_jerk_trajectory("left", [rest("left")] * 2, [0.5]))
    reply = robot.execute(sweep, rate=50.0)
    assert reply.approach_duration == 0.0
    assert calls(sim) == before + 3  # the left arm to rest and its hold, the sweep


def test_an_approach_through_the_other_arm_is_refused(sim: SimProcess) -> None:
    """The left arm held across the way; the right arm asked to hold at
    the way's other end: the approach there is refused, nothing sent."""
    robot = RobotBridge(NaoqiClient(sim.url))
    robot.execute(minimum_jerk_trajectory("left", [LEFT_ACROSS] * 2, [0.5]))
    robot.execute(minimum_jerk_trajectory("right", [SWEEP_FROM] * 2, [0.5]))
    before = calls(sim)
    hold = minimum_jerk_trajectory("right", [SWEEP_TO] * 2, [0.5])
    with pytest.raises(TrajectoryRefusedError, match="at approach frame") as err:
        robot.execute(hold, rate=50.0)
    assert "NAO's left " in str(err.value)
    assert calls(sim) == before


@pytest.mark.parametrize(
    "posture", [[float("nan"), 0.0, 0.0, -0.5, 0.0], [0.0, 0.0, 0.0, -0.5]]
)
def test_an_other_arm_posture_that_is_no_posture_is_refused(posture) -> None:
    """A NaN would make every distance NaN, which is never "too near"."""
    with pytest.raises(InvalidInputError, match="left arm's posture must be 5 finite"):
        with_other_arm("right", posture)
