"""Where the robot's first step starts: the arm as commanded, not the plan.

The bridge against the simulated NAO over real libqi, in this process. The
commands the sim received (its log) are rebuilt as frames counted from the
angles the arm was commanded to before each one, and checked against the
bridge's own limits: what reached the robot, from where it was.
"""

from __future__ import annotations

import math
import threading
import time
from typing import Any

import numpy as np
import pytest

from bridge.checks import check_frames
from bridge.limits import FrameLimits
from bridge.minimum_jerk import minimum_jerk_trajectory
from bridge.naoqi_client import NaoqiClient
from bridge.robot_bridge import RobotBridge
from bridge.sim import SimProcess
from bridge.sim.log import read_log
from shared.errors import RobotBusyError, TrajectoryRefusedError
from shared.messages import CommandFrames
from shared.robot.postures import rest

#: A posture inside every range, away from rest.
POSTURE = rest("right") + np.array([-0.3, -0.1, 0.0, 0.3, 0.2])
NAMES = ["RShoulderPitch", "RShoulderRoll", "RElbowYaw", "RElbowRoll", "RWristYaw"]


@pytest.fixture
def bridge(sim: SimProcess) -> RobotBridge:
    """A bridge whose arm holds ``POSTURE`` (reached by an approach)."""
    robot = RobotBridge(NaoqiClient(sim.url))
    robot.execute(minimum_jerk_trajectory("right", [POSTURE, POSTURE], [0.5]))
    return robot


def received(sim: SimProcess) -> list[CommandFrames]:
    """Every angleInterpolation the sim took, as frames from where the arm was."""
    assert sim.log_path is not None
    calls = [
        e
        for e in read_log(sim.log_path)
        if e["event"] == "call" and e["method"] == "angleInterpolation"
    ]
    commanded = rest("right")
    out = []
    for call in calls:
        assert call["names"] == NAMES
        positions = np.array(call["angles"]).T
        out.append(
            CommandFrames(
                arm="right",
                rate=1.0 / call["times"][0][0],
                joint_names=NAMES,
                start=commanded.tolist(),
                times=call["times"][0],
                positions=positions.tolist(),
            )
        )
        commanded = positions[-1]
    return out


def hold_off_start(offset_deg: float) -> Any:
    """A 1 s hold at ``POSTURE`` with ShoulderRoll ``offset_deg`` off."""
    start = POSTURE.copy()
    start[1] += math.radians(offset_deg)
    return minimum_jerk_trajectory("right", [start, start], [1.0])


def test_a_first_step_over_a_limit_from_the_arm_is_approached(
    sim: SimProcess, bridge: RobotBridge
) -> None:
    """0.45 deg off (within the 0.5 deg counted as at the start) at 100 fps:
    from where the arm is, the first frame is a step of 0.45 deg in 10 ms,
    over the acceleration limit; the bridge approaches first, and everything
    the robot received passes the limits from where the arm was."""
    limits = FrameLimits.for_arm("right")
    trajectory = hold_off_start(0.45)
    with pytest.raises(TrajectoryRefusedError, match="counted from where the arm is"):
        bridge.execute(trajectory, rate=100.0, approach=False)
    reply = bridge.execute(trajectory, rate=100.0)
    assert reply.approach_duration >= 0.5
    frames = received(sim)
    assert len(frames) == 4  # the fixture's approach and hold, these two
    for sent in frames:
        check_frames(sent, limits)


def test_a_first_step_within_the_limits_needs_no_approach(
    sim: SimProcess, bridge: RobotBridge
) -> None:
    """0.05 deg off at 25 fps: the step keeps every limit, no approach."""
    reply = bridge.execute(hold_off_start(0.05), rate=25.0, approach=False)
    assert reply.approach_duration == 0.0
    frames = received(sim)
    assert len(frames) == 3  # the fixture's approach and hold, this hold
    for sent in frames:
        check_frames(sent, FrameLimits.for_arm("right"))


def test_an_arm_moved_by_another_client_is_busy(
    sim: SimProcess, bridge: RobotBridge
) -> None:
    """Another client (as Choregraphe would) moves the arm for 2 s: the
    bridge refuses with robot_busy and sends nothing; once the arm has
    stopped it plays."""
    other = NaoqiClient(sim.url)
    target = rest("right")
    keys = [[float(v)] for v in target]
    moving = threading.Thread(
        target=other.call,
        args=("angleInterpolation", NAMES, keys, [[2.0]] * 5, True),
        kwargs={"timeout": 5.0},
    )
    moving.start()
    time.sleep(0.3)
    with pytest.raises(RobotBusyError, match="has an arm still moving") as caught:
        bridge.execute(minimum_jerk_trajectory("right", [target, target], [0.5]))
    assert caught.value.remaining is None
    moving.join()
    assert sim.log_path is not None
    log = read_log(sim.log_path)
    assert not [e for e in log if e["event"] == "interrupted"]
    reply = bridge.execute(minimum_jerk_trajectory("right", [target, target], [0.5]))
    assert reply.approach_duration == 0.0


def test_an_arm_held_still_by_another_clients_task_is_busy(
    sim: SimProcess, bridge: RobotBridge
) -> None:
    """Another client's blocking call moves the arm for 1 s, then holds it
    for 3 s (a dwell): its task still holds the joints, though two readings
    agree. The bridge refuses with robot_busy and sends nothing, instead of
    commanding on top of it (the sim would interrupt that task; a NAO would
    postpone the bridge's call, then jump); once the task ends it plays."""
    other = NaoqiClient(sim.url)
    target = rest("right")
    keys = [[float(v), float(v)] for v in target]
    holding = threading.Thread(
        target=other.call,
        args=("angleInterpolation", NAMES, keys, [[1.0, 4.0]] * 5, True),
        kwargs={"timeout": 8.0},
    )
    holding.start()
    time.sleep(1.3)  # in the dwell: the arm holds still until 4 s
    assert not other.call("areResourcesAvailable", ["RArm"])
    assert other.call("areResourcesAvailable", ["LArm"])
    with pytest.raises(RobotBusyError, match="held by a motion task") as caught:
        bridge.execute(minimum_jerk_trajectory("right", [target, target], [0.5]))
    assert caught.value.remaining is None
    holding.join()
    assert sim.log_path is not None
    assert not [e for e in read_log(sim.log_path) if e["event"] == "interrupted"]
    assert len(received(sim)) == 3  # the fixture's approach and hold, the other's
    reply = bridge.execute(minimum_jerk_trajectory("right", [target, target], [0.5]))
    assert reply.approach_duration == 0.0
