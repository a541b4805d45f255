"""A plan request may say where the other arm is held (``other_arm``): the
plan keeps clear of it as of NAO's body (services/planner/clear_of.py).

On the planner, on the command line, and end to end: the simulated NAO
over real libqi holds its left arm across the right arm's way; the bridge
refuses the plan made without knowing it, and plays the one made with it.
"""

from __future__ import annotations

import json

import numpy as np
import pytest

from bridge.minimum_jerk import minimum_jerk_trajectory
from bridge.naoqi_client import NaoqiClient
from bridge.robot_bridge import RobotBridge
from bridge.sim import SimProcess
from services.planner.pipeline import plan
from shared.errors import JointLimitError, TargetInBodyError, TrajectoryRefusedError
from shared.messages import PlanRequest, parse
from shared.robot import load_arm
from shared.robot.body import MARGIN, check_target_clear, closest
from shared.robot.other_arm import with_other_arm
from tests.armplan_cli import armplan

#: The left arm held across the front of the chest (its hand on the right).
LEFT_ACROSS = [0.54, -0.09, -0.56, -1.05, -1.54]
#: A right-arm reach whose planned way, blind to the left arm, runs 2 mm
#: into that hand; both its ends are clear of it.
START = [-0.9551, 0.1494, 0.3192, 0.4635, 0.2247]
TARGET = [0.1391, -0.0821, 0.0568]
#: Within the right arm's reach, inside the left hand held across.
IN_LEFT_HAND = [0.1287, -0.0056, 0.0776]


def _request(**more: object) -> PlanRequest:
    return PlanRequest(arm="right", start=START, targets=[{"position": TARGET}], **more)


def test_a_plan_told_where_the_other_arm_is_keeps_clear_of_it() -> None:
    """Blind to the left arm the plan comes within the margin of it; told
    where it is, the plan keeps the margin from it and from the body."""
    arm, parts = load_arm("right"), with_other_arm("right", LEFT_ACROSS)
    blind = plan(_request()).trajectory
    near = closest(arm, blind.positions, parts)
    assert near.clearance < MARGIN and near.body_part.startswith("left ")
    aware = plan(_request(other_arm=LEFT_ACROSS)).trajectory
    assert closest(arm, aware.positions, parts).clearance >= MARGIN
    assert np.allclose(aware.positions[0], START)


def test_the_bridge_refuses_the_blind_plan_and_plays_the_aware_one(
    sim: SimProcess,
) -> None:
    """On the simulated NAO, the left arm held across: the bridge, which
    reads where that arm is, refuses the plan made without it (nothing
    sent) and plays the plan made with it."""
    robot = RobotBridge(NaoqiClient(sim.url))
    robot.execute(minimum_jerk_trajectory("left", [np.array(LEFT_ACROSS)] * 2, [0.5]))
    robot.execute(minimum_jerk_trajectory("right", [np.array(START)] * 2, [1.5]))
    with pytest.raises(TrajectoryRefusedError, match=r"NAO's left \w+") as err:
        robot.execute(plan(_request()).trajectory)
    assert err.value.quantity == "clearance"
    reply = robot.execute(plan(_request(other_arm=LEFT_ACROSS)).trajectory)
    assert reply.approach_duration == 0.0


def test_a_target_in_the_other_arm_is_refused_naming_it() -> None:
    request = PlanRequest(
        arm="right", targets=[{"position": IN_LEFT_HAND}], other_arm=LEFT_ACROSS
    )
    with pytest.raises(TargetInBodyError, match="NAO's left hand") as err:
        plan(request)
    assert "the other arm where the request holds it" in str(err.value)
    check_target_clear(load_arm("right"), IN_LEFT_HAND)  # clear of the body


def test_the_other_arms_posture_must_be_within_its_own_ranges() -> None:
    """The right arm's angles given for the left: its ElbowRoll is out of
    the left arm's range, and the error says which arm's posture it is."""
    with pytest.raises(JointLimitError, match="other arm's posture"):
        plan(_request(other_arm=[0.0, -0.3, 0.0, 1.0, 0.0]))


def test_the_field_is_left_out_of_the_json_when_not_given() -> None:
    assert "other_arm" not in json.loads(_request().model_dump_json())
    given = _request(other_arm=LEFT_ACROSS).model_dump_json()
    assert parse(PlanRequest, given).other_arm == tuple(LEFT_ACROSS)


def test_the_command_line_takes_the_other_arm() -> None:
    """--other-arm: a target in the left hand is refused naming it; NaN is
    refused naming the option; the reach above plans clear of it."""
    target = [str(v) for v in IN_LEFT_HAND]
    arm_at = [str(v) for v in LEFT_ACROSS]
    done = armplan("plan", "--target", *target, "--other-arm", *arm_at, "--json")
    assert done.returncode == 1, done.stderr
    assert json.loads(done.stdout)["error"]["kind"] == "target_in_body"
    done = armplan("plan", "--target", *target, "--other-arm", "nan", *arm_at[1:])
    assert done.returncode != 0
    assert "--other-arm" in done.stderr and "Traceback" not in done.stderr
    done = armplan(
        "plan",
        "--start",
        *(str(v) for v in START),
        "--target",
        *(str(v) for v in TARGET),
        "--other-arm",
        *arm_at,
        "--json",
    )
    assert done.returncode == 0, done.stderr
    positions = json.loads(done.stdout)["positions"]
    parts = with_other_arm("right", LEFT_ACROSS)
    assert closest(load_arm("right"), positions, parts).clearance >= MARGIN
