"""The planner's wrist path: a great-circle swing, its distance set by the bend."""

from __future__ import annotations

import math

import numpy as np
import pytest

from armplan.experiments.normalised_time import tau_grid
from armplan.experiments.subject_reach import subject_reaches
from services.planner.wrist_path import _slerp as great_circle
from services.planner.wrist_path import bend_radius, minimum_jerk, reach_path
from shared.demos import synthesize
from shared.robot import ArmModel
from shared.robot.arm_model import load_arm
from shared.robot.postures import rest


def _bend(distance: np.ndarray, upper: float, fore: float) -> np.ndarray:
    """Elbow bend [rad] at each shoulder-to-wrist distance [m] (law of cosines)."""
    cos = (distance**2 - upper**2 - fore**2) / (2.0 * upper * fore)
    return np.arccos(np.clip(cos, -1.0, 1.0))


def _random_reaches(arm: ArmModel, count: int) -> list[tuple[np.ndarray, np.ndarray]]:
    """(start posture, goal) pairs, both within the joint ranges (seeded)."""
    rng = np.random.default_rng(7)
    lower, upper = arm.limits.lower, arm.limits.upper
    return [
        (rng.uniform(lower, upper), arm.fk(rng.uniform(lower, upper)).wrist)
        for _ in range(count)
    ]


def test_the_path_starts_at_the_wrist_and_ends_on_the_goal(arm: ArmModel) -> None:
    start = rest(arm.side)
    goal = np.array([0.12, 0.1 * -arm.side.sign, 0.05])
    path = reach_path(arm, start, goal, 0.734, 100.0)
    assert len(path.times) == 75  # ceil(73.4) + 1
    assert np.allclose(np.diff(path.times), 0.01)
    assert np.array_equal(path.positions[0], arm.fk(start).wrist)
    assert np.array_equal(path.positions[-1], goal)


def test_the_elbow_bend_behind_the_distance_moves_by_minimum_jerk(
    arm: ArmModel,
) -> None:
    """Identity: the bend that gives each point's distance is the two ends'
    bends interpolated with the minimum-jerk progress, on every reach."""
    upper, fore = arm.upper_arm_length, arm.forearm_length
    for start, goal in _random_reaches(arm, 50):
        path = reach_path(arm, start, goal, 1.0, 100.0)
        shoulder = arm.fk(start).shoulder
        distance = np.linalg.norm(path.positions - shoulder, axis=1)
        bend = _bend(distance, upper, fore)
        progress = minimum_jerk(path.times / path.times[-1])
        wanted = bend[0] + progress * (bend[-1] - bend[0])
        assert np.max(np.abs(bend - wanted)) < 1e-6


def test_every_point_lies_between_the_two_ends_distances(arm: ArmModel) -> None:
    """The distance from the shoulder changes monotonically from start to goal,
    so a path whose ends are in NAO's reach shell stays in it."""
    for start, goal in _random_reaches(arm, 50):
        path = reach_path(arm, start, goal, 0.8, 100.0)
        distance = np.linalg.norm(path.positions - arm.fk(start).shoulder, axis=1)
        steps = np.diff(distance) * np.sign(distance[-1] - distance[0])
        assert np.all(steps >= -1e-12)


def test_the_direction_turns_on_the_great_circle_with_the_progress(
    arm: ArmModel,
) -> None:
    for start, goal in _random_reaches(arm, 20):
        path = reach_path(arm, start, goal, 1.0, 100.0)
        out = path.positions - arm.fk(start).shoulder
        unit = out / np.linalg.norm(out, axis=1, keepdims=True)
        whole = math.acos(float(np.clip(unit[0] @ unit[-1], -1.0, 1.0)))
        if whole < 0.05:
            continue
        turned = np.arccos(np.clip(unit @ unit[0], -1.0, 1.0))
        progress = minimum_jerk(path.times / path.times[-1])
        assert np.max(np.abs(turned - progress * whole)) < 1e-6
        normal = np.cross(unit[0], unit[-1])
        assert np.max(np.abs(unit @ normal)) < 1e-9


def test_bend_radius_keeps_both_ends_exactly() -> None:
    """Outside the two segments' span (NAO's elbow offset) the ends still hold."""
    progress = np.linspace(0.0, 1.0, 11)
    radius = bend_radius(0.170, 0.120, progress, 0.106, 0.056)
    assert radius[0] == pytest.approx(0.170, abs=1e-15)
    assert radius[-1] == pytest.approx(0.120, abs=1e-15)


def test_the_bend_law_is_nearer_the_demonstrations_than_the_distance_law() -> None:
    """On synthetic grid reaches (seeded), the wrist path whose distance follows
    the elbow's bend lies nearer the subjects' mean wrist paths than one whose
    distance itself moves by minimum jerk (the earlier law)."""
    arm = load_arm("right")
    upper, fore = arm.upper_arm_length, arm.forearm_length
    demos = synthesize(3, subjects=3, trials=2, points=(1, 6, 11, 16))
    tau = tau_grid(51)
    shoulder = arm.fk(rest(arm.side)).shoulder
    errors: dict[str, list[float]] = {"bend": [], "distance": []}
    progress = minimum_jerk(tau)
    for reach in subject_reaches(demos, tau):
        a, b = reach.wrist[0] - shoulder, reach.wrist[-1] - shoulder
        ra, rb = float(np.linalg.norm(a)), float(np.linalg.norm(b))
        laws = {
            "bend": bend_radius(ra, rb, progress, upper, fore),
            "distance": ra + progress * (rb - ra),
        }
        direction = great_circle(a / ra, b / rb, progress)  # the same for both
        for name, radius in laws.items():
            path = shoulder + direction * radius[:, None]
            errors[name].append(
                float(np.mean(np.linalg.norm(path - reach.wrist, axis=1)))
            )
    bend, distance = np.mean(errors["bend"]), np.mean(errors["distance"])
    print(
        f"\nmean wrist distance: bend law {bend * 100:.3f} cm, "
        f"distance law {distance * 100:.3f} cm"
    )
    assert bend < distance
