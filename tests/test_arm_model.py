"""Forward kinematics, Jacobians, centres of mass and gravity of the arm model."""

from __future__ import annotations

import math

import numpy as np
import pytest
from conftest import random_posture

from shared.errors import JointLimitError, UnknownArmError
from shared.robot import ArmModel, Side, load_arm
from shared.robot.postures import mirror, rest

G = 9.81


def _rot(axis: str, angle: float) -> np.ndarray:
    c, s = math.cos(angle), math.sin(angle)
    if axis == "x":
        return np.array([[1, 0, 0], [0, c, -s], [0, s, c]])
    if axis == "y":
        return np.array([[c, 0, s], [0, 1, 0], [-s, 0, c]])
    return np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]])


def hand_written_fk(side: Side, q: np.ndarray) -> dict[str, np.ndarray]:
    """NAO arm FK from the SPEC's table, written out by hand (no URDF, no pinocchio)."""
    s = 1.0 if side is Side.RIGHT else -1.0
    shoulder = np.array([0.0, -0.098 * s, 0.100])
    r = _rot("y", q[0]) @ _rot("z", q[1])
    elbow = shoulder + r @ np.array([0.105, -0.015 * s, 0.0])
    r = r @ _rot("x", q[2]) @ _rot("z", q[3])
    wrist = elbow + r @ np.array([0.05595, 0.0, 0.0])
    r = r @ _rot("x", q[4])
    hand = wrist + r @ np.array([0.05775, 0.0, -0.01231])
    return {"shoulder": shoulder, "elbow": elbow, "wrist": wrist, "hand": hand}


def test_fk_agrees_with_a_hand_written_chain(
    arm: ArmModel, rng: np.random.Generator
) -> None:
    """Pinocchio on the URDF and the hand-written chain agree to 1e-9 m."""
    for _ in range(300):
        q = random_posture(arm, rng)
        points = arm.fk(q)
        expected = hand_written_fk(arm.side, q)
        for name, value in expected.items():
            np.testing.assert_allclose(getattr(points, name), value, atol=1e-9, rtol=0)


def test_left_arm_mirrors_right(rng: np.random.Generator) -> None:
    """Mirrored postures give points mirrored in the torso's sagittal plane."""
    right, left = load_arm("right"), load_arm("left")
    flip = np.array([1.0, -1.0, 1.0])
    for _ in range(100):
        q = random_posture(right, rng)
        for a, b in zip(right.fk(q), left.fk(mirror(q)), strict=True):
            np.testing.assert_allclose(a * flip, b, atol=1e-12)


@pytest.mark.parametrize("point", ["elbow", "wrist", "hand"])
def test_linear_jacobian_matches_finite_differences(
    arm: ArmModel, rng: np.random.Generator, point: str
) -> None:
    """d(point)/dq equals central differences of FK."""
    h = 1e-6
    for _ in range(50):
        q = random_posture(arm, rng)
        fd = np.column_stack(
            [
                (getattr(arm.fk(q + h * e), point) - getattr(arm.fk(q - h * e), point))
                / (2 * h)
                for e in np.eye(5)
            ]
        )
        np.testing.assert_allclose(arm.jacobian(q, point), fd, atol=1e-8)


def test_angular_jacobian_matches_finite_differences(
    arm: ArmModel, rng: np.random.Generator
) -> None:
    """The wrist frame's angular Jacobian equals the rotation's finite change."""
    h = 1e-6
    for _ in range(50):
        q = random_posture(arm, rng)
        r0 = arm.rotation(q, "wrist")
        cols = []
        for e in np.eye(5):
            dr = (
                arm.rotation(q + h * e, "wrist") - arm.rotation(q - h * e, "wrist")
            ) / (2 * h)
            w = dr @ r0.T  # skew-symmetric: [omega]_x
            cols.append([w[2, 1], w[0, 2], w[1, 0]])
        np.testing.assert_allclose(
            arm.frame_jacobian(q, "wrist")[3:], np.array(cols).T, atol=1e-8
        )


def test_kinematics_pass_agrees_with_single_calls(
    arm: ArmModel, rng: np.random.Generator
) -> None:
    """The one-pass Kinematics gives the same numbers as the separate methods."""
    q = random_posture(arm, rng)
    kin = arm.kinematics(q)
    points = arm.fk(q)
    np.testing.assert_allclose(kin.wrist, points.wrist, atol=1e-15)
    np.testing.assert_allclose(kin.elbow, points.elbow, atol=1e-15)
    np.testing.assert_allclose(kin.wrist_jacobian, arm.jacobian(q, "wrist"), atol=1e-15)
    np.testing.assert_allclose(kin.elbow_jacobian, arm.jacobian(q, "elbow"), atol=1e-15)
    np.testing.assert_allclose(kin.wrist_rotation, arm.rotation(q, "wrist"), atol=1e-15)


def test_gravity_energy_is_mass_times_height(
    arm: ArmModel, rng: np.random.Generator
) -> None:
    """f_GPE = m_u g h_u + m_l g h_l (eq. 16) from the two segments' centres of mass."""
    for _ in range(50):
        q = random_posture(arm, rng)
        coms = arm.segment_coms(q)
        h_u, h_l = coms.heights
        expected = coms.upper_mass * G * h_u + coms.lower_mass * G * h_l
        assert arm.gravity_energy(q) == pytest.approx(expected, abs=1e-12)


def test_segment_masses_are_the_spec_links() -> None:
    """Upper arm = shoulder + biceps links; lower arm = elbow + forearm + hand."""
    coms = load_arm("right").segment_coms(rest("right"))
    assert coms.upper_mass == pytest.approx(0.09304 + 0.15777)
    assert coms.lower_mass == pytest.approx(0.06483 + 0.07761 + 0.18533)


def test_gravity_gradient_matches_finite_differences(
    arm: ArmModel, rng: np.random.Generator
) -> None:
    """d(f_GPE)/dq, the gravity torques, equals central differences of the energy."""
    h = 1e-6
    for _ in range(50):
        q = random_posture(arm, rng)
        fd = [
            (arm.gravity_energy(q + h * e) - arm.gravity_energy(q - h * e)) / (2 * h)
            for e in np.eye(5)
        ]
        np.testing.assert_allclose(arm.gravity_gradient(q), fd, atol=1e-9)


def test_hanging_arm_has_its_centres_of_mass_below_the_shoulder() -> None:
    """At rest both segments' centres of mass are lower than the shoulder."""
    arm = load_arm("right")
    coms = arm.segment_coms(rest("right"))
    shoulder_z = arm.fk(rest("right")).shoulder[2]
    assert coms.upper[2] < shoulder_z and coms.lower[2] < coms.upper[2]


def test_reach_span_bounds_sampled_postures(
    arm: ArmModel, rng: np.random.Generator
) -> None:
    """Every posture's shoulder-wrist distance is in arm.reach; the span is tight."""
    distances = []
    for _ in range(2000):
        p = arm.fk(random_posture(arm, rng))
        distances.append(np.linalg.norm(p.wrist - p.shoulder))
    low, high = arm.reach
    assert low - 1e-9 <= min(distances) and max(distances) <= high + 1e-9
    assert min(distances) - low < 0.003 and high - max(distances) < 0.003


def test_distance_span_at_an_elbow_roll_is_what_elbow_yaw_sweeps(
    arm: ArmModel, rng: np.random.Generator
) -> None:
    """With ElbowRoll held, FK over ElbowYaw's whole range (the other joints
    anywhere) stays within distance_span_at and meets both of its ends."""
    yaws = np.linspace(arm.limits.lower[2], arm.limits.upper[2], 2001)
    for _ in range(20):
        q = random_posture(arm, rng)
        low, high = arm.distance_span_at(q[3])
        distances = []
        for yaw in yaws:
            q[2] = yaw
            p = arm.fk(q)
            distances.append(np.linalg.norm(p.wrist - p.shoulder))
        assert low - 1e-12 <= min(distances) and max(distances) <= high + 1e-12
        assert min(distances) - low < 1e-8 and high - max(distances) < 1e-8


def test_limits_come_from_the_robot_file() -> None:
    """Ranges and speeds are the URDF's, in the paper's joint order."""
    arm = load_arm("left")
    assert arm.joint_names == (
        "LShoulderPitch",
        "LShoulderRoll",
        "LElbowYaw",
        "LElbowRoll",
        "LWristYaw",
    )
    np.testing.assert_allclose(arm.limits.lower[[1, 3]], [-0.314159, -1.54462])
    np.testing.assert_allclose(
        arm.limits.velocity, [8.26797, 7.19407, 8.26797, 7.19407, 24.6229]
    )


def test_limit_check_names_the_joint() -> None:
    """A posture out of range raises JointLimitError naming the joint and range."""
    arm = load_arm("right")
    q = rest("right")
    q[3] = 2.0
    with pytest.raises(JointLimitError, match=r"RElbowRoll = 2\.00000 rad is outside"):
        arm.limits.check(q)


def test_a_posture_in_degrees_is_named_as_such(
    arm: ArmModel, rng: np.random.Generator
) -> None:
    """A posture typed in degrees (``--start 90 -10 45 30 0``) was refused as
    "90 rad" with no word of the likely slip. A random posture in range,
    given in degrees, is refused with its radians, which lie in every range;
    no hint when the degrees read as radians would not fit, nor when fewer
    than two angles are beyond a turn (a posture slightly out of range, or
    one typo in radians)."""
    checked = 0
    for _ in range(20):
        q = random_posture(arm, rng)
        degrees = np.rad2deg(q)
        if np.sum(np.abs(degrees) > 2.0 * np.pi) < 2:
            continue
        checked += 1
        with pytest.raises(JointLimitError) as caught:
            arm.limits.check(degrees, where="in the start posture")
        said = caught.value.message.split("it looks like degrees: angles are in ")[1]
        radians = said.split("(")[1].split(")")[0]
        assert np.allclose([float(x) for x in radians.split(", ")], q, atol=1e-4)
    assert checked >= 15
    beyond = arm.limits.upper + 0.05  # out of range, but no angle beyond a turn
    with pytest.raises(JointLimitError) as caught:
        arm.limits.check(beyond)
    assert "degrees" not in caught.value.message
    unfit = np.rad2deg(arm.limits.upper) + 30.0  # degrees, out of range as such
    with pytest.raises(JointLimitError) as caught:
        arm.limits.check(unfit)
    assert "degrees" not in caught.value.message
    typo = arm.limits.middle.copy()  # radians, one elbow roll mistyped
    typo[3] = 8.0 * np.sign(typo[3])
    with pytest.raises(JointLimitError) as caught:
        arm.limits.check(typo)
    assert "degrees" not in caught.value.message


def test_a_posture_of_the_other_arm_is_named_with_its_mirror(
    arm: ArmModel, rng: np.random.Generator
) -> None:
    """A right-arm posture typed for the left arm (or the reverse) was refused
    naming ElbowRoll's range, with no word of the signs. It is refused with
    the mirror image, ShoulderPitch kept and the other joints negated, which
    lies in every range; a posture whose mirror does not fit gets no such
    word."""
    other = load_arm(Side.LEFT if arm.side is Side.RIGHT else Side.RIGHT)
    this, that = arm.side.value, other.side.value
    for _ in range(20):
        q = random_posture(other, rng)
        with pytest.raises(JointLimitError) as caught:
            arm.limits.check(q, where="in the start posture")
        said = caught.value.message.split(
            f"; if it is a posture of the {that} arm, the {this} arm's mirror of it "
            "(ShoulderPitch kept, the other joints negated) is ("
        )[1]
        mirrored = [float(x) for x in said.split(")")[0].split(", ")]
        assert np.allclose(mirrored, mirror(q), atol=1e-4)
        assert arm.limits.contains(mirror(q))
    unfit = arm.limits.middle.copy()  # ElbowRoll's sign wrong, WristYaw too far
    unfit[3], unfit[4] = -unfit[3], 3.0
    with pytest.raises(JointLimitError) as caught:
        arm.limits.check(unfit)
    assert "mirror" not in caught.value.message


def test_unknown_arm_is_a_typed_error() -> None:
    """A wrong arm name raises UnknownArmError naming it."""
    with pytest.raises(UnknownArmError, match="unknown arm 'middle'"):
        load_arm("middle")
