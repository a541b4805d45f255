"""A palm the IK cannot face: the target is reached, and the error says why
(services/ik/reach_then_turn.py)."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from services.ik.palm_reached import palm_reached
from services.ik.reach_then_turn import WRIST_YAW, turn_wrist
from services.ik.solver import solve
from shared.errors import (
    PalmRollOutOfRangeError,
    UnreachableTargetError,
    error_from_wire,
)
from shared.geometry.palm import roll_error
from shared.messages import Method
from shared.robot import load_arm
from tests.armplan_cli import armplan
from tests.clear_draws import clear_target

#: A target in front of the right shoulder and a palm facing forward: the
#: roll that faces it there needs WristYaw beyond its range.
TARGET = np.array([0.148, -0.06, 0.131])
FORWARD = np.array([0.9985, -0.02737, 0.04761])


def _unit(v: np.ndarray) -> np.ndarray:
    return v / np.linalg.norm(v)


def test_every_palm_refused_at_a_reached_target_is_named_as_the_palm() -> None:
    """150 targets at the wrist of clear random postures, random palms: each
    solve with the palm either succeeds or, where the target is reached
    without it, says the palm cannot be faced, never that the solver stopped
    short of the target (13 of them did). Some are refused, so the check
    means something."""
    arm = load_arm("right")
    rng = np.random.default_rng(0)
    refused = 0
    for _ in range(150):
        target = clear_target(arm, rng)
        palm = _unit(rng.normal(size=3))
        try:
            solve(arm, target, palm=palm)
        except PalmRollOutOfRangeError as error:
            refused += 1
            assert solve(arm, target).error < 1e-4
            low, high = error.wrist_yaw_range
            assert not low <= error.wrist_yaw <= high
            assert np.linalg.norm(arm.fk(np.array(error.posture)).wrist - target) < 1e-4
    assert refused >= 5


@pytest.mark.parametrize("method", list(Method))
def test_the_error_gives_a_posture_at_the_target_and_the_roll_it_needs(
    method: Method,
) -> None:
    """For each method: the posture named reaches the target; at the WristYaw
    named the palm's roll is right (no roll left to make), and that WristYaw
    is beyond the range by the least turn; at the bound nearest it the palm
    is the angle named from the wanted direction, and no WristYaw within the
    range comes nearer (sampled)."""
    arm = load_arm("right")
    with pytest.raises(PalmRollOutOfRangeError) as refused:
        solve(arm, TARGET, palm=FORWARD, method=method)
    error = refused.value
    q = np.array(error.posture)
    assert np.linalg.norm(arm.fk(q).wrist - TARGET) < 1e-4
    facing = q.copy()
    facing[WRIST_YAW] = error.wrist_yaw
    assert abs(roll_error(arm.rotation(facing, "wrist"), arm.side.sign, FORWARD)) < 1e-9
    low, high = error.wrist_yaw_range
    beyond = max(low - error.wrist_yaw, error.wrist_yaw - high)
    for turn in (-2.0 * math.pi, 2.0 * math.pi):
        other = error.wrist_yaw + turn
        assert max(low - other, other - high) > beyond
    angles = []
    for yaw in np.linspace(low, high, 201):
        q[WRIST_YAW] = yaw
        angles.append(palm_reached(arm, q, tuple(FORWARD)).angle_deg)
    assert min(angles) == pytest.approx(math.degrees(error.nearest_angle), abs=1e-6)


def test_a_roll_within_range_turns_the_wrist_in_place() -> None:
    """turn_wrist on a posture at the target: the wrist stays put (WristYaw
    turns about the forearm, on which the wrist lies), WristYaw stays in its
    range, the roll is made, and the palm is then off the wanted direction
    by exactly the angle the direction makes with the plane across the
    forearm (what a roll cannot change)."""
    arm = load_arm("right")
    rng = np.random.default_rng(3)
    turned = 0
    while turned < 20:
        q = rng.uniform(arm.limits.lower, arm.limits.upper)
        palm = _unit(rng.normal(size=3))
        try:
            after = turn_wrist(arm, q, arm.fk(q).wrist, palm)
        except PalmRollOutOfRangeError:
            continue
        turned += 1
        assert np.allclose(after[:WRIST_YAW], q[:WRIST_YAW])
        assert np.linalg.norm(arm.fk(after).wrist - arm.fk(q).wrist) < 1e-12
        lower, upper = arm.limits.lower[WRIST_YAW], arm.limits.upper[WRIST_YAW]
        assert lower <= after[WRIST_YAW] <= upper
        rotation = arm.rotation(after, "wrist")
        assert abs(roll_error(rotation, arm.side.sign, palm)) < 1e-9
        axis = np.asarray(rotation)[:, 0]
        expected = math.degrees(math.asin(min(1.0, abs(float(palm @ axis)))))
        reached = palm_reached(arm, after, tuple(palm)).angle_deg
        assert reached == pytest.approx(expected, abs=1e-6)


def test_the_error_crosses_the_wire_as_itself() -> None:
    """A service's palm error comes back to its caller as the same class, a
    kind of unreachable_target, with its facts."""
    with pytest.raises(PalmRollOutOfRangeError) as refused:
        solve(load_arm("right"), TARGET, palm=FORWARD)
    wire = json.loads(json.dumps(refused.value.to_wire()))
    again = error_from_wire(wire)
    assert isinstance(again, PalmRollOutOfRangeError)
    assert isinstance(again, UnreachableTargetError)
    assert again.message == refused.value.message
    assert again.evidence["wrist_yaw"] == pytest.approx(refused.value.wrist_yaw)


@pytest.mark.parametrize("command", ["ik", "plan"])
def test_the_commands_say_the_palm_not_the_reach(command: str) -> None:
    """`armplan ik` and `armplan plan` with that palm: exit 1, the kind
    palm_roll_out_of_range in the JSON, and the text names WristYaw."""
    target = [f"{v:g}" for v in TARGET]
    palm = [f"{v:g}" for v in FORWARD]
    done = armplan(command, "--target", *target, "--palm", *palm, "--json")
    assert done.returncode == 1, done.stderr
    error = json.loads(done.stdout)["error"]
    assert error["kind"] == "palm_roll_out_of_range"
    assert "WristYaw" in error["message"]
    assert "the IK solver stopped" not in error["message"]


def test_a_target_the_arm_cannot_reach_with_a_palm_stays_out_of_reach() -> None:
    """Within the reach shell, but no posture puts the wrist there (the
    solver stops short without a palm too): the target is blamed, not the
    palm, whatever the palm."""
    arm = load_arm("right")
    target = np.array([-0.15, -0.098, 0.1])
    with pytest.raises(UnreachableTargetError):
        solve(arm, target)  # no palm: out of reach already
    for palm in (FORWARD, np.array([0.0, 0.0, 1.0]), np.array([0.0, -1.0, 0.0])):
        with pytest.raises(UnreachableTargetError) as refused:
            solve(arm, target, palm=palm)
        assert not isinstance(refused.value, PalmRollOutOfRangeError)
        assert "the IK solver stopped" in str(refused.value)
