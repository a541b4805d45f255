"""Motion limits: speeds from the URDF, acceleration and jerk defaults, overrides."""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest

from shared.errors import InvalidInputError
from shared.robot import ArmModel, load_arm, motion_limits
from shared.robot.motion_limits import ACCELERATION_TIME, JERK_TIME


def test_speeds_and_ranges_come_from_the_robot_description(arm: ArmModel) -> None:
    """Velocity, lower and upper are the URDF's numbers, not copies of them."""
    limits = motion_limits(arm.limits)
    assert limits.names == arm.joint_names
    assert np.array_equal(limits.velocity, arm.limits.velocity)
    assert np.array_equal(limits.lower, arm.limits.lower)
    assert np.array_equal(limits.upper, arm.limits.upper)


def test_defaults_reach_full_speed_and_full_acceleration_in_the_stated_times() -> None:
    """acceleration = v / ACCELERATION_TIME and jerk = acceleration / JERK_TIME."""
    joints = load_arm("right").limits
    limits = motion_limits(joints)
    assert np.allclose(limits.acceleration * ACCELERATION_TIME, joints.velocity)
    assert np.allclose(limits.jerk * JERK_TIME, limits.acceleration)


def test_default_accelerations_need_less_than_three_quarters_of_the_torque(
    arm: ArmModel,
) -> None:
    """Link inertia at full acceleration plus gravity stays below 75 % of effort."""
    limits = motion_limits(arm.limits)
    data = arm.model.createData()
    rng = np.random.default_rng(0)
    for q in rng.uniform(arm.limits.lower, arm.limits.upper, size=(300, 5)):
        inertia = pin.crba(arm.model, data, q)
        inertia = np.triu(inertia) + np.triu(inertia, 1).T
        gravity = pin.computeGeneralizedGravity(arm.model, data, q)
        torque = np.abs(inertia) @ limits.acceleration + np.abs(gravity)
        assert np.all(torque < 0.75 * arm.limits.effort)


def test_limits_can_be_set_for_all_joints_or_per_joint() -> None:
    """A scalar applies to every joint; five values to one joint each."""
    joints = load_arm("right").limits
    limits = motion_limits(joints, acceleration=20.0, jerk=[1, 2, 3, 4, 5])
    assert np.array_equal(limits.acceleration, np.full(5, 20.0))
    assert np.array_equal(limits.jerk, [1, 2, 3, 4, 5])
    assert np.allclose(motion_limits(joints, acceleration=10.0).jerk, 10.0 / JERK_TIME)


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({"acceleration": -1.0}, "acceleration limit of RShoulderPitch is -1.0"),
        ({"jerk": [1, 2, 0, 4, 5]}, "jerk limit of RElbowYaw is 0.0"),
        ({"jerk": [1, 2, np.inf, 4, 5]}, "jerk limit of RElbowYaw is inf"),
        ({"acceleration": [1, 2]}, r"acceleration limits need one value or 5 values"),
    ],
)
def test_bad_limits_are_refused_by_name(
    kwargs: dict[str, object], message: str
) -> None:
    """Non-positive, infinite or misshapen limits raise InvalidInputError."""
    with pytest.raises(InvalidInputError, match=message):
        motion_limits(load_arm("right").limits, **kwargs)  # type: ignore[arg-type]


def test_limits_are_read_only_and_scale_together() -> None:
    """Arrays cannot be written; scaled() scales speed, acceleration and jerk."""
    limits = motion_limits(load_arm("right").limits)
    with pytest.raises(ValueError, match="read-only"):
        limits.jerk[0] = 1.0
    half = limits.scaled(0.5)
    assert np.allclose(half.velocity, 0.5 * limits.velocity)
    assert np.allclose(half.jerk, 0.5 * limits.jerk)
    assert np.array_equal(half.upper, limits.upper)
    with pytest.raises(InvalidInputError, match="outside"):
        limits.scaled(1.5)
