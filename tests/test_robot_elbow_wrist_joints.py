"""The closed-form posture from elbow and wrist points, against the kinematics
and against the least squares it replaces where it answers."""

from __future__ import annotations

from functools import partial

import numpy as np
import pytest
from scipy.optimize import least_squares  # type: ignore[import-untyped]

from shared.demos.posture_from_points import joints_from_points
from shared.robot import load_arm
from shared.robot.arm_model import ArmModel, ArmPoints
from shared.robot.elbow_wrist_joints import EXACT, elbow_wrist_joints
from shared.robot.postures import rest

SIDES = ["right", "left"]


def _within(arm: ArmModel, rng: np.random.Generator, n: int) -> np.ndarray:
    """``n`` postures drawn within the arm's ranges [rad], shape (n, 5)."""
    return rng.uniform(arm.limits.lower, arm.limits.upper, size=(n, 5))


@pytest.mark.parametrize("side", SIDES)
def test_the_shoulder_is_where_the_kinematics_puts_it(side: str) -> None:
    arm = load_arm(side)
    assert np.array_equal(arm.shoulder_position, arm.fk(rest(arm.side)).shoulder)


@pytest.mark.parametrize("side", SIDES)
def test_the_posture_of_the_points_is_found_again(side: str) -> None:
    """Forward kinematics, then the closed form: the same four joints."""
    arm = load_arm(side)
    for q in _within(arm, np.random.default_rng(7), 500):
        points = arm.fk(q)
        found = elbow_wrist_joints(arm, points.elbow, points.wrist, rest(arm.side))
        assert found is not None
        np.testing.assert_allclose(found, q[:4], rtol=0.0, atol=1e-11)


def _point_error(arm: ArmModel, points: ArmPoints, joints: np.ndarray) -> np.ndarray:
    """Elbow and wrist of ``joints`` [rad], (4,), less ``points`` [m], shape (6,)."""
    at = arm.fk(np.concatenate((joints, [0.0])))
    return np.concatenate((at.elbow - points.elbow, at.wrist - points.wrist))


@pytest.mark.parametrize("side", SIDES)
def test_it_agrees_with_least_squares_from_a_warm_start(side: str) -> None:
    """scipy's bounded least squares on the same points, from a posture
    0.05 rad away, ends on the same posture within its own tolerance (it
    stops about 1e-5 rad short), and nearer the points it is not."""
    arm = load_arm(side)
    rng = np.random.default_rng(8)
    lower, upper = arm.limits.lower[:4], arm.limits.upper[:4]
    for q in _within(arm, rng, 100):
        q[3] = np.sign(q[3]) * max(abs(q[3]), 0.3)  # a bent elbow: ElbowYaw counts
        points = arm.fk(q)
        start = np.clip(q[:4] + rng.uniform(-0.05, 0.05, 4), lower, upper)

        error = partial(_point_error, arm, points)
        fitted = least_squares(error, start, bounds=(lower, upper), xtol=1e-12).x
        found = elbow_wrist_joints(arm, points.elbow, points.wrist, start)
        assert found is not None
        np.testing.assert_allclose(found, fitted, rtol=0.0, atol=1e-4)
        ours, theirs = np.abs(error(found)).max(), np.abs(error(fitted)).max()
        assert ours <= EXACT and ours <= theirs + 1e-15


@pytest.mark.parametrize("side", SIDES)
def test_points_off_the_arms_lengths_or_ranges_have_none(side: str) -> None:
    """An upper arm 1 cm long, or an elbow bent past its range: no answer,
    and ``joints_from_points`` gives the nearest posture within the ranges."""
    arm = load_arm(side)
    q = np.array([0.3, -0.4, 0.5, 0.8, 0.0]) * np.array([1, arm.side.sign] * 2 + [1])
    points = arm.fk(q)
    shoulder = arm.shoulder_position
    longer = shoulder + 1.1 * (points.elbow - shoulder)
    assert elbow_wrist_joints(arm, longer, points.wrist, q) is None
    past = q.copy()
    past[3] = arm.side.sign * 1.7  # ElbowRoll ends at 1.5446 rad
    bent = arm.fk(past)
    assert elbow_wrist_joints(arm, bent.elbow, bent.wrist, q) is None
    nearest = joints_from_points(arm, bent.elbow, bent.wrist, guess=q)
    assert np.all((arm.limits.lower <= nearest) & (nearest <= arm.limits.upper))
    reached = arm.fk(nearest)
    assert np.linalg.norm(reached.wrist - bent.wrist) > EXACT


@pytest.mark.parametrize("side", SIDES)
def test_joints_from_points_keeps_the_wrist_yaw_it_is_given(side: str) -> None:
    arm = load_arm(side)
    q = _within(arm, np.random.default_rng(9), 1)[0]
    points = arm.fk(q)
    found = joints_from_points(arm, points.elbow, points.wrist, guess=q)
    np.testing.assert_allclose(found, q, rtol=0.0, atol=1e-11)
