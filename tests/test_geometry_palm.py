"""The palm's roll about the forearm: its error and its exact rate."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from services.ik.kernel import chain_for
from services.ik.task import WristTask
from shared.geometry.palm import DEGENERATE, roll_error, roll_rate
from shared.robot import ArmModel
from tests.conftest import random_posture

STEP = 1e-6  # [rad], central differences


def _approx(value: float) -> object:
    return pytest.approx(value, abs=1e-6)


def _unit(v: np.ndarray) -> np.ndarray:
    return v / np.linalg.norm(v)


def _away_from_the_forearm(rotation: np.ndarray, palm: np.ndarray) -> bool:
    """The palm is far enough off the forearm axis for roll to matter (20 deg)."""
    return abs(palm @ rotation[:, 0]) < np.cos(np.radians(20.0))


def test_roll_rate_is_the_derivative_of_the_roll_error() -> None:
    """Turning the wrist frame by a small angle h about any axis u changes
    roll_error by -h u . roll_rate (central differences, both hands), where
    the forearm's own swing counts too, not just the part along it."""
    rng = np.random.default_rng(3)
    checked, off_axis = 0, []
    for _ in range(400):
        rotation = Rotation.random(random_state=rng).as_matrix()
        palm, axis = _unit(rng.normal(size=3)), _unit(rng.normal(size=3))
        sign = float(rng.choice([-1.0, 1.0]))
        if not _away_from_the_forearm(rotation, palm):
            continue
        turned = [Rotation.from_rotvec(s * STEP * axis).as_matrix() @ rotation
                  for s in (1.0, -1.0)]  # fmt: skip
        after, before = (roll_error(r, sign, palm) for r in turned)
        if abs(after - before) > 1.0:  # across atan2's branch cut
            continue
        rate = np.array(roll_rate(rotation, sign, palm))
        assert -(after - before) / (2 * STEP) == _approx(axis @ rate)
        off_axis.append(abs(axis @ rate - axis @ rotation[:, 0]))
        checked += 1
    assert checked > 200
    assert max(off_axis) > 0.1  # the projection on the forearm alone is not it


def test_roll_rate_along_the_forearm_is_one() -> None:
    """About the forearm axis itself the roll is made one for one."""
    rng = np.random.default_rng(4)
    for _ in range(50):
        rotation = Rotation.random(random_state=rng).as_matrix()
        palm = _unit(rng.normal(size=3))
        if not _away_from_the_forearm(rotation, palm):
            continue
        rate = np.array(roll_rate(rotation, 1.0, palm))
        assert rotation[:, 0] @ rate == _approx(1.0)


def test_roll_rate_is_the_forearm_axis_where_roll_does_not_matter() -> None:
    """Within 5 degrees of the forearm axis (roll_error 0 there) the rate is
    the forearm axis."""
    rotation = Rotation.from_euler("xyz", [0.3, -0.2, 0.5]).as_matrix()
    tilt = 0.5 * np.arcsin(DEGENERATE)
    palm = np.cos(tilt) * rotation[:, 0] + np.sin(tilt) * rotation[:, 1]
    assert roll_error(rotation, 1.0, palm) == 0.0
    np.testing.assert_array_equal(roll_rate(rotation, 1.0, palm), rotation[:, 0])


def test_the_wrist_task_roll_column_is_the_joint_derivative(
    arm: ArmModel, rng: np.random.Generator
) -> None:
    """The wrist task's roll entry for joint k is minus the derivative of its
    roll error in q_k (central differences on the arm's own kinematics)."""
    chain = chain_for(arm)
    for _ in range(20):
        q = random_posture(arm, rng)
        palm = _unit(rng.normal(size=3))
        st = chain.state(q.tolist())
        if not _away_from_the_forearm(np.array(st.rot), palm):
            continue
        task = WristTask.make(st.p_wrist, palm, arm.side.sign)
        cols = task.residual(st)[1]
        for k in range(5):
            moved = [
                task.residual(chain.state((q + s * STEP * np.eye(5)[k]).tolist()))[0]
                for s in (1.0, -1.0)
            ]
            derivative = (moved[0][3] - moved[1][3]) / (2 * STEP)
            if abs(derivative) > 1e3:  # across atan2's branch cut
                continue
            assert cols[k][3] == _approx(-derivative)
