"""The simulated NAO's argument forms and checks (pure functions)."""

from __future__ import annotations

import pytest

from bridge.sim.commands import (
    KeyCommand,
    check_range,
    check_speed,
    key_commands,
    per_joint,
)
from bridge.sim.errors import SimCommandError
from bridge.sim.joints import CHAINS, expand_names, joint_specs


def test_joint_limits_come_from_the_robot_description() -> None:
    """Both arms and hands, with the URDF's ranges and speed limits."""
    specs = joint_specs()
    assert len(specs) == 12
    assert specs["RElbowRoll"].lower == pytest.approx(0.0349066)
    assert specs["LShoulderRoll"].upper == pytest.approx(1.32645)
    assert specs["RWristYaw"].velocity == pytest.approx(24.6229)
    assert (specs["RHand"].lower, specs["RHand"].upper) == (0.0, 1.0)


def test_chain_names_expand_to_joints() -> None:
    """'RArm' is the five arm joints and the hand; unknown names are errors."""
    assert expand_names("RArm") == CHAINS["RArm"] and len(CHAINS["RArm"]) == 6
    assert expand_names(["LHand", "RElbowYaw"]) == ["LHand", "RElbowYaw"]
    with pytest.raises(SimCommandError, match="unknown joint or chain 'HeadYaw'"):
        expand_names("HeadYaw")


def test_almotion_argument_forms() -> None:
    """A number, a list per joint, or a list of lists per joint."""
    assert per_joint(0.5, 2, "a") == [[0.5], [0.5]]
    assert per_joint([0.1, 0.2], 1, "a") == [[0.1, 0.2]]
    assert per_joint([0.1, 0.2], 2, "a") == [[0.1], [0.2]]
    assert per_joint([[0.1, 0.2], 0.3], 2, "a") == [[0.1, 0.2], [0.3]]
    with pytest.raises(SimCommandError, match="a has 3 entries for 2 joints"):
        per_joint([1, 2, 3], 2, "a")
    with pytest.raises(SimCommandError, match="must be finite"):
        per_joint(float("nan"), 1, "a")


def test_key_times_must_increase_from_above_zero() -> None:
    """Times at 0, decreasing, or fewer than the angles are refused."""
    with pytest.raises(SimCommandError, match="must increase from above 0"):
        key_commands(["RElbowYaw"], [0.1, 0.2], [0.0, 1.0])
    with pytest.raises(SimCommandError, match="must increase from above 0"):
        key_commands(["RElbowYaw"], [0.1, 0.2], [1.0, 0.5])
    with pytest.raises(SimCommandError, match="2 values for 1 times"):
        key_commands(["RElbowYaw"], [[0.1, 0.2]], [[1.0]])


def test_out_of_range_and_over_speed_keys_are_refused_not_clamped() -> None:
    """The error names the key, the value or speed, and the limit."""
    spec = joint_specs()["RShoulderRoll"]
    with pytest.raises(
        SimCommandError, match=r"RShoulderRoll key 2 = 0\.50000 rad is outside"
    ):
        check_range(KeyCommand("RShoulderRoll", [0.5, 1.0], [0.0, 0.5]), spec)
    with pytest.raises(
        SimCommandError, match=r"key 1 \(t = 0\.100 s\) needs 10\.000 rad/s"
    ):
        check_speed(KeyCommand("RShoulderRoll", [0.1], [-1.0]), spec, start=0.0)
    check_speed(KeyCommand("RShoulderRoll", [0.2], [-1.0]), spec, start=0.0)
