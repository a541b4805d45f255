"""The robot description holds the SPEC's numbers; the left arm mirrors the right."""

from __future__ import annotations

import xml.etree.ElementTree as ET

import numpy as np
import pytest

from shared.robot.arm_model import urdf_text

# The SPEC's table, typed here independently of the URDF.
SPEC_JOINTS = {
    # name: (origin R arm, axis, lower R, upper R, velocity, effort)
    "ShoulderPitch": ((0, -0.098, 0.100), (0, 1, 0), -2.08567, 2.08567, 8.26797, 1.329),
    "ShoulderRoll": ((0, 0, 0), (0, 0, 1), -1.32645, 0.314159, 7.19407, 1.783),
    "ElbowYaw": ((0.105, -0.015, 0), (1, 0, 0), -2.08567, 2.08567, 8.26797, 1.547),
    "ElbowRoll": ((0, 0, 0), (0, 0, 1), 0.0349066, 1.54462, 7.19407, 1.532),
    "WristYaw": ((0.05595, 0, 0), (1, 0, 0), -1.82387, 1.82387, 24.6229, 0.4075),
    "Hand": ((0.05775, 0, -0.01231), (1, 0, 0), 0.0, 1.0, 8.33, 0.292),
}
# Child links of each joint: mass and centre of mass (R arm).
SPEC_MASSES = {
    "ShoulderPitch": (0.09304, (-0.00165, 0.02663, 0.00014)),
    "ShoulderRoll": (0.15777, (0.02455, -0.00563, 0.0033)),
    "ElbowYaw": (0.06483, (-0.02744, 0, -0.00014)),
    "ElbowRoll": (0.07761, (0.02556, -0.00281, 0.00076)),
    "WristYaw": (0.18533, (0.03434, 0.00088, 0.00308)),
}
MIRRORED_RANGES = {"ShoulderRoll", "ElbowRoll"}


def _vec(text: str) -> np.ndarray:
    return np.array([float(v) for v in text.split()])


@pytest.fixture(scope="module")
def robot() -> ET.Element:
    return ET.fromstring(urdf_text())


def _joint(robot: ET.Element, name: str) -> ET.Element:
    found = robot.find(f"joint[@name='{name}']")
    assert found is not None, name
    return found


def _link(robot: ET.Element, name: str) -> ET.Element:
    found = robot.find(f"link[@name='{name}']")
    assert found is not None, name
    return found


@pytest.mark.parametrize("prefix,sign", [("R", 1.0), ("L", -1.0)])
def test_joints_match_the_spec_table(
    robot: ET.Element, prefix: str, sign: float
) -> None:
    """Origins, axes, ranges, speeds and torques are the SPEC's (left: mirrored)."""
    for name, (origin, axis, lower, upper, velocity, effort) in SPEC_JOINTS.items():
        joint = _joint(robot, prefix + name)
        xyz = _vec(joint.find("origin").get("xyz"))  # type: ignore[union-attr]
        expected = np.array(origin) * np.array([1.0, sign, 1.0])
        np.testing.assert_allclose(xyz, expected, atol=0, rtol=0)
        np.testing.assert_array_equal(_vec(joint.find("axis").get("xyz")), axis)  # type: ignore[union-attr]
        limit = joint.find("limit")
        assert limit is not None
        if sign < 0 and name in MIRRORED_RANGES:
            lower, upper = -upper, -lower
        assert float(limit.get("lower")) == lower  # type: ignore[arg-type]
        assert float(limit.get("upper")) == upper  # type: ignore[arg-type]
        assert float(limit.get("velocity")) == velocity  # type: ignore[arg-type]
        assert float(limit.get("effort")) == effort  # type: ignore[arg-type]


@pytest.mark.parametrize("prefix,sign", [("R", 1.0), ("L", -1.0)])
def test_masses_match_the_spec_table(
    robot: ET.Element, prefix: str, sign: float
) -> None:
    """Each joint's child link carries the SPEC's mass and centre of mass."""
    for name, (mass, com) in SPEC_MASSES.items():
        child = _joint(robot, prefix + name).find("child").get("link")  # type: ignore[union-attr]
        inertial = _link(robot, child).find("inertial")  # type: ignore[arg-type]
        assert inertial is not None
        assert float(inertial.find("mass").get("value")) == mass  # type: ignore[union-attr, arg-type]
        xyz = _vec(inertial.find("origin").get("xyz"))  # type: ignore[union-attr]
        np.testing.assert_allclose(
            xyz, np.array(com) * np.array([1.0, sign, 1.0]), rtol=0
        )


def test_both_arms_hang_from_the_torso(robot: ET.Element) -> None:
    """The base link is the torso and both shoulders attach to it."""
    for prefix in "RL":
        parent = _joint(robot, prefix + "ShoulderPitch").find("parent")
        assert parent is not None and parent.get("link") == "torso"
