"""Closed-form IK (eq. 11-13) against the paper's formulas and against GPM."""

from __future__ import annotations

import math

import numpy as np
import pytest
from conftest import random_posture

from services.ik.geometric import (
    elbow_roll_candidates,
    solve_elbow_triangle,
    solve_shoulder_rotation,
    solve_wrist_turn,
    triangle_elbow_angle,
)
from services.ik.iterate import solve_gpm
from services.ik.measures import NoMeasure
from services.ik.task import WristTask
from shared.errors import InvalidInputError, PrimitiveCannotReachError
from shared.geometry import palm_normal, roll_error
from shared.robot import ArmModel


def _inner(arm: ArmModel, rng: np.random.Generator) -> np.ndarray:
    """A posture away from the limits (so a nearby one-joint move stays in range)."""
    return np.clip(
        random_posture(arm, rng), arm.limits.lower + 0.25, arm.limits.upper - 0.25
    )


def test_offset_triangle_reduces_to_eq_11_12() -> None:
    """Without the elbow offset, th4 = pi - Omega exactly (eq. 11-12)."""
    lu, lf = 0.105, 0.05595
    for th4 in np.linspace(0.05, 1.5, 20):
        distance = math.sqrt(lu**2 + lf**2 + 2 * lu * lf * math.cos(th4))
        assert triangle_elbow_angle(lu, lf, distance) == pytest.approx(th4, abs=1e-9)


def test_elbow_triangle_recovers_the_elbow_roll(
    arm: ArmModel, rng: np.random.Generator
) -> None:
    """Changing only ElbowRoll, the closed form finds that ElbowRoll again."""
    for _ in range(200):
        start = _inner(arm, rng)
        goal = start.copy()
        goal[3] = rng.uniform(arm.limits.lower[3], arm.limits.upper[3])
        target = arm.fk(goal).wrist
        sol = solve_elbow_triangle(arm, start, target, 1e-6)
        assert sol.residual < 1e-9
        assert goal[3] in [
            pytest.approx(r, abs=1e-9)
            for r in elbow_roll_candidates(
                arm, start[2], float(np.linalg.norm(target - arm.fk(start).shoulder))
            )
        ]
        np.testing.assert_array_equal(np.delete(sol.q, 3), np.delete(start, 3))


def test_elbow_triangle_reaches_what_elbow_roll_reaches(
    arm: ArmModel, rng: np.random.Generator
) -> None:
    """From any start, the closed form lands on every target that moving only
    ElbowRoll reaches, near a straight arm too: there the distance is not
    monotonic in ElbowRoll (elbow offset), and of the two roots the one
    nearer the start's ElbowRoll can miss the target by millimetres."""
    low, high = arm.limits.lower[3], arm.limits.upper[3]
    for k in range(200):
        start = random_posture(arm, rng)
        goal = start.copy()
        bent = rng.uniform(0.0, 0.15 if k % 2 else 1.0)  # half near a straight arm
        goal[3] = low + (high - low) * (bent if arm.side.sign > 0 else 1.0 - bent)
        target = arm.fk(goal).wrist
        sol = solve_elbow_triangle(arm, start, target, 1e-6)
        assert np.linalg.norm(arm.fk(sol.q).wrist - target) < 1e-9
        np.testing.assert_array_equal(np.delete(sol.q, 3), np.delete(start, 3))


def test_shoulder_rotation_recovers_the_elbow_yaw(
    arm: ArmModel, rng: np.random.Generator
) -> None:
    """Changing only ElbowYaw, eq. 13 finds that ElbowYaw again."""
    for _ in range(200):
        start = _inner(arm, rng)
        goal = start.copy()
        goal[2] = start[2] + rng.uniform(-1.0, 1.0)
        goal[2] = np.clip(goal[2], arm.limits.lower[2], arm.limits.upper[2])
        sol = solve_shoulder_rotation(arm, start, arm.fk(goal).wrist, 1e-6)
        assert sol.q[2] == pytest.approx(goal[2], abs=1e-7)
        np.testing.assert_array_equal(np.delete(sol.q, 2), np.delete(start, 2))


@pytest.mark.parametrize("joint", [2, 3])
def test_closed_form_and_gpm_agree(
    arm: ArmModel, rng: np.random.Generator, joint: int
) -> None:
    """Where both apply (one active joint, target on its circle), GPM finds the
    closed-form posture."""
    solve = solve_shoulder_rotation if joint == 2 else solve_elbow_triangle
    for _ in range(40):
        start = _inner(arm, rng)
        goal = start.copy()
        goal[joint] = np.clip(
            start[joint] + rng.uniform(-0.5, 0.5),
            arm.limits.lower[joint],
            arm.limits.upper[joint],
        )
        target = arm.fk(goal).wrist
        closed = solve(arm, start, target, 1e-6)
        task = WristTask.make(target, None, arm.side.sign)
        q, _ = solve_gpm(arm, task, (joint,), NoMeasure(), start)
        np.testing.assert_allclose(q, closed.q, atol=1e-6)


def test_off_circle_targets_are_refused(
    arm: ArmModel, rng: np.random.Generator
) -> None:
    """A target the single joint cannot reach raises PrimitiveCannotReachError."""
    start = _inner(arm, rng)
    target = arm.fk(start).wrist + np.array([0.0, 0.0, 0.03])
    for solve, name in [
        (solve_elbow_triangle, "E_R W_P"),
        (solve_shoulder_rotation, "S_R W_P"),
    ]:
        with pytest.raises(
            PrimitiveCannotReachError, match=f"primitive '{name}' cannot reach"
        ):
            solve(arm, start, target, 1e-4)


def test_wrist_turn_faces_the_palm(arm: ArmModel, rng: np.random.Generator) -> None:
    """W_R turns WristYaw so that the palm faces the wanted direction's projection."""
    for _ in range(100):
        start = _inner(arm, rng)
        goal = start.copy()
        goal[4] = rng.uniform(-1.5, 1.5)
        palm = palm_normal(arm.rotation(goal, "wrist"), arm.side.sign)
        sol = solve_wrist_turn(arm, start, arm.fk(start).wrist, palm, 1e-6)
        assert sol.q[4] == pytest.approx(goal[4], abs=1e-9)
        assert roll_error(
            arm.rotation(sol.q, "wrist"), arm.side.sign, palm
        ) == pytest.approx(0.0, abs=1e-9)


def test_wrist_turn_needs_a_palm(arm: ArmModel) -> None:
    """W_R without a palm direction is an InvalidInputError naming the palm."""
    q = (arm.limits.lower + arm.limits.upper) / 2
    with pytest.raises(InvalidInputError, match="palm direction"):
        solve_wrist_turn(arm, q, arm.fk(q).wrist, None, 1e-4)
