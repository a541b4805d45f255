"""Motion variables: two implementations agree; zero at the goal; scale-free."""

from __future__ import annotations

import numpy as np
import pytest

from services.fit.labelling import infer_labels
from services.fit.roll import roll_to_go, roll_to_go_at
from services.fit.variables import (
    E_P,
    E_R,
    S_R,
    W_P,
    W_R,
    motion_variables,
    variables_at,
)
from shared.demos import Trial, nao_arm_size, synthesize
from shared.demos.wrist_roll import roll_to_go as exact_roll
from shared.robot import ArmModel
from tests.conftest import random_posture


def _states(arm: ArmModel, rng: np.random.Generator, n: int) -> tuple[np.ndarray, ...]:
    points = [arm.fk(random_posture(arm, rng)) for _ in range(n)]
    shoulder = np.array([p.shoulder for p in points])
    elbow = np.array([p.elbow for p in points])
    wrist = np.array([p.wrist for p in points])
    return shoulder, elbow, wrist


def test_numpy_and_plain_float_versions_agree(
    arm: ArmModel, rng: np.random.Generator
) -> None:
    """motion_variables and variables_at give the same five numbers."""
    shoulder, elbow, wrist = _states(arm, rng, 40)
    goal = wrist[::-1].copy()
    roll = rng.uniform(-3, 3, 40)
    many = motion_variables(
        shoulder, elbow, wrist, goal, arm.upper_arm_length, arm.forearm_length, roll
    )
    for k in range(40):
        one = variables_at(
            tuple(shoulder[k].tolist()),
            tuple(elbow[k].tolist()),
            tuple(wrist[k].tolist()),
            tuple(goal[k].tolist()),
            arm.upper_arm_length,
            arm.forearm_length,
            float(roll[k]),
        )
        np.testing.assert_allclose(one, many[k], atol=1e-12)


def test_all_zero_at_the_goal(arm: ArmModel, rng: np.random.Generator) -> None:
    """With the wrist on the goal nothing is left to change."""
    shoulder, elbow, wrist = _states(arm, rng, 20)
    values = motion_variables(
        shoulder, elbow, wrist, wrist, arm.upper_arm_length, arm.forearm_length
    )
    np.testing.assert_allclose(values, 0.0, atol=1e-7)


def test_rotating_the_whole_arm_is_shoulder_rotation_only(
    arm: ArmModel, rng: np.random.Generator
) -> None:
    """A goal reached by turning the arm about the shoulder: only S_R, by the angle."""
    shoulder, elbow, wrist = _states(arm, rng, 1)
    axis = np.array([0.3, -0.5, 0.8]) / np.linalg.norm([0.3, -0.5, 0.8])
    angle = 0.4
    k = np.array(
        [[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]]
    )
    turn = np.eye(3) + np.sin(angle) * k + (1 - np.cos(angle)) * k @ k
    goal = shoulder[0] + turn @ (wrist[0] - shoulder[0])
    values = motion_variables(
        shoulder, elbow, wrist, goal, arm.upper_arm_length, arm.forearm_length
    )[0]
    w = wrist[0] - shoulder[0]
    expected = np.arccos((turn @ w) @ w / (w @ w))
    assert values[S_R] == pytest.approx(expected, abs=1e-9)
    assert values[W_P] == pytest.approx(0.0, abs=1e-12)
    assert values[E_R] == pytest.approx(0.0, abs=1e-7)
    assert values[E_P] > 0.0 and values[W_R] == 0.0


def test_variables_do_not_depend_on_arm_size(
    arm: ArmModel, rng: np.random.Generator
) -> None:
    """Scaling positions and lengths together leaves every variable unchanged."""
    shoulder, elbow, wrist = _states(arm, rng, 10)
    goal = wrist[::-1].copy()
    lengths = (arm.upper_arm_length, arm.forearm_length)
    base = motion_variables(shoulder, elbow, wrist, goal, *lengths)
    scaled = motion_variables(
        3 * shoulder, 3 * elbow, 3 * wrist, 3 * goal, *(3 * v for v in lengths)
    )
    np.testing.assert_allclose(scaled, base, atol=1e-12)


@pytest.fixture(scope="module")
def reaches() -> list[Trial]:
    return synthesize(11, subjects=2, trials=1).trials


def test_roll_to_go_two_versions_zero_at_end_exact_at_last_phase(
    reaches: list[Trial],
) -> None:
    """W_R: numpy and float versions agree, 0 at the end, exact while the elbow ends."""
    size = nao_arm_size("right")
    for trial in reaches[::5]:
        axis = trial.wrist_frame[:, :, 1]
        args = (trial.target, axis[-1], size.upper_arm, size.forearm)
        many = roll_to_go(trial.shoulder, trial.elbow, trial.wrist, axis, *args)
        for k in range(0, len(many), 7):
            one = roll_to_go_at(
                trial.shoulder[k], trial.elbow[k], trial.wrist[k], axis[k], *args
            )
            assert one == pytest.approx(many[k], abs=1e-10)
        assert many[-1] == pytest.approx(0.0, abs=1e-9)
        last = np.array([label == "E_R W_P" for label in trial.labels])
        exact = np.abs(
            exact_roll(trial.shoulder, trial.elbow, trial.wrist, trial.wrist_frame)
        )
        np.testing.assert_allclose(many[last], exact[last], atol=0.03)


def test_labels_from_recorded_motion_match_the_generators(
    reaches: list[Trial],
) -> None:
    """Labelling by joint speeds agrees with the generator on most samples."""
    agreed = total = 0
    for trial in reaches:
        inferred = infer_labels(trial)
        agreed += sum(a == b for a, b in zip(inferred, trial.labels, strict=True))
        total += len(inferred)
    assert agreed / total > 0.85
