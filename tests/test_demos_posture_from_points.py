"""NAO postures from retargeted points: WristYaw for a palm out of range, both arms."""

from __future__ import annotations

import math

import numpy as np
import pytest

from shared.demos.posture_from_points import (
    joint_path_from_points,
    wrist_yaw_for_palm,
)
from shared.robot import ArmModel, load_arm
from shared.robot.postures import mirror

#: Reflection of the torso frame's y axis: right-arm points to left-arm points.
FLIP_Y = np.diag([1.0, -1.0, 1.0])
#: WristYaw's upper limit, the lower one's opposite, for both arms [rad].
LIMIT = float(load_arm("right").limits.upper[4])


def palm_at(arm: ArmModel, q: np.ndarray, yaw: float) -> np.ndarray:
    """The palm normal, shape (3,), of posture ``q`` turned to WristYaw ``yaw`` [rad].

    Computed from the frame at yaw 0 (cos(yaw) y0 + sin(yaw) z0), so ``yaw``
    may lie outside the joint's range.
    """
    frame = arm.rotation(np.concatenate((q[:4], [0.0])), "wrist")
    return math.cos(yaw) * frame[:, 1] + math.sin(yaw) * frame[:, 2]


@pytest.mark.parametrize("wanted", [2.0, 2.9, -2.0, -2.9])
def test_from_the_middle_the_wrist_stops_on_the_palm_side(wanted: float) -> None:
    """Yaw 0 (the rest guess) and a palm beyond one limit give that limit.

    The tie between the limits (both 1.824 rad from yaw 0) went to the lower
    one whatever side the palm was beyond."""
    arm = load_arm("right")
    q = np.array([0.3, -0.4, 1.0, 0.8, 0.0])
    assert wrist_yaw_for_palm(arm, q, palm_at(arm, q, wanted)) == pytest.approx(
        math.copysign(LIMIT, wanted), abs=1e-3
    )


def test_inside_the_range_the_wrist_stops_on_the_palm_side() -> None:
    """From yaw 0.5 a palm 0.18 rad beyond the lower limit gives the lower limit,
    not the upper one 2.46 rad round the other way."""
    arm = load_arm("right")
    q = np.array([0.3, -0.4, 1.0, 0.8, 0.5])
    yaw = wrist_yaw_for_palm(arm, q, palm_at(arm, q, -2.0))
    assert yaw == pytest.approx(-LIMIT, abs=1e-3)


def test_the_left_wrist_yaw_mirrors_the_right(rng: np.random.Generator) -> None:
    """Mirrored posture and palm give the mirrored WristYaw, in range or not."""
    right, left = load_arm("right"), load_arm("left")
    for _ in range(200):
        q = rng.uniform(right.limits.lower, right.limits.upper)
        q[4] = rng.choice([0.0, rng.uniform(-LIMIT, LIMIT)])
        wanted = rng.uniform(-math.pi, math.pi)
        found = wrist_yaw_for_palm(right, q, palm_at(right, q, wanted))
        palm = palm_at(left, mirror(q), -wanted)
        assert wrist_yaw_for_palm(left, mirror(q), palm) == pytest.approx(-found)


def test_a_left_reach_is_the_mirror_of_the_right() -> None:
    """A reach whose palm starts beyond a WristYaw limit, and its mirror image,
    solved from each arm's rest posture, give mirrored joint paths."""
    right, left = load_arm("right"), load_arm("left")
    path = np.linspace([1.4, -0.1, 1.6, 0.3, -2.3], [0.9, -0.3, 1.3, 0.9, -1.2], 12)
    points = [right.fk(q) for q in path]
    frames = np.array(
        [
            right.rotation(np.concatenate((q[:4], [0.0])), "wrist")
            @ _turn_about_x(q[4])
            for q in path
        ]
    )
    elbow = np.array([p.elbow for p in points])
    wrist = np.array([p.wrist for p in points])
    found_right = joint_path_from_points(right, elbow, wrist, frames)
    found_left = joint_path_from_points(
        left, elbow @ FLIP_Y, wrist @ FLIP_Y, FLIP_Y @ frames @ FLIP_Y
    )
    assert found_right[0, 4] == pytest.approx(-LIMIT, abs=1e-3)
    np.testing.assert_allclose(found_left, mirror(found_right), atol=1e-6)


def _turn_about_x(angle: float) -> np.ndarray:
    """The rotation [rad] about the x axis, shape (3, 3)."""
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]])


def test_wrist_yaw_out_of_range_waits_at_the_nearer_limit() -> None:
    """A palm half a turn from yaw 0 keeps the wrist at the limit it is at."""
    arm = load_arm("right")
    q = np.array([0.3, -0.4, 1.0, 0.8, 1.7])
    frame = arm.rotation(np.array([0.3, -0.4, 1.0, 0.8, 0.0]), "wrist")
    behind = -frame[:, 1]  # yaw pi, outside [-1.824, 1.824]
    assert wrist_yaw_for_palm(arm, q, behind) == pytest.approx(arm.limits.upper[4])
    q[4] = -1.7
    assert wrist_yaw_for_palm(arm, q, behind) == pytest.approx(arm.limits.lower[4])
