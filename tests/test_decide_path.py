"""Deciding along a path inside the IK tracker; the IK service can replay it."""

from __future__ import annotations

import numpy as np
import pytest

from services.decide.decider import CANDIDATES
from services.decide.path import decide_path, decide_wrist_path
from services.fit import MotionModel, default_model
from services.ik.track import track_path
from services.planner.wrist_path import reach_path
from shared.messages import Decision, WristPath, parse
from shared.primitives import BY_NAME
from shared.robot import ArmModel
from shared.robot.postures import rest


@pytest.fixture(scope="module")
def model() -> MotionModel:
    return default_model()


def _reach(arm: ArmModel, duration: float = 0.8) -> tuple[np.ndarray, np.ndarray]:
    start = rest(arm.side)
    kin = arm.kinematics(start)
    goal = np.array([0.12, 0.09 * (-arm.side.sign), 0.05])
    path = reach_path(kin.shoulder, kin.wrist, goal, duration, 100.0)
    return path.times, path.positions


def test_decision_names_matrix_and_every_g(arm: ArmModel, model: MotionModel) -> None:
    """One point decision per path point: the winner, its matrix, all eight g."""
    times, positions = _reach(arm)
    decision, tracked = decide_path(model, arm, positions, rest(arm.side), times=times)
    assert len(decision.points) == len(positions) == len(tracked.q)
    assert parse(Decision, decision.to_json()) == decision
    for point in decision.points:
        assert point.matrix == BY_NAME[point.primitive].matrix
        assert list(point.g) == list(CANDIDATES)
        assert point.g[point.primitive] == max(point.g.values())
    assert decision.primitives[0] == "S_R E_P W_P"
    assert np.linalg.norm(tracked.wrist[-1] - positions[-1]) < 1e-5


def test_ik_replay_of_the_decision_is_bit_identical(
    arm: ArmModel, model: MotionModel
) -> None:
    """track_path with the recorded primitives gives exactly the same joints."""
    times, positions = _reach(arm)
    start = rest(arm.side)
    decision, tracked = decide_path(model, arm, positions, start, times=times)
    again = track_path(
        arm, positions, start, lambda k, kin: BY_NAME[decision.points[k].primitive]
    )
    assert np.array_equal(again.q, tracked.q)
    assert again.labels == tracked.labels


def test_palm_direction_decisions_replay_too(arm: ArmModel, model: MotionModel) -> None:
    """With a wanted palm direction W_R is observed; the replay still matches."""
    times, positions = _reach(arm, 0.6)
    start = rest(arm.side)
    palm = np.array([0.0, arm.side.sign, -1.0]) / np.sqrt(2.0)
    decision, tracked = decide_path(
        model, arm, positions, start, palm=palm, times=times
    )
    again = track_path(
        arm,
        positions,
        start,
        lambda k, kin: BY_NAME[decision.points[k].primitive],
        palm=palm,
    )
    assert np.array_equal(again.q, tracked.q)


def test_wrist_path_message_gives_the_same_decision(model: MotionModel) -> None:
    """The decide service's request (a WristPath) decides like decide_path."""
    from shared.robot import load_arm

    arm = load_arm("right")
    times, positions = _reach(arm)
    message = WristPath(
        arm="right", times=times.tolist(), positions=[tuple(p) for p in positions]
    )
    direct, _ = decide_path(model, arm, positions, rest("right"), times=times)
    assert decide_wrist_path(model, arm, message) == direct


def test_slower_sampling_still_decides_every_point(model: MotionModel) -> None:
    """A path at 50 Hz scales the transition table; every point is decided."""
    from shared.robot import load_arm

    arm = load_arm("right")
    start = rest("right")
    kin = arm.kinematics(start)
    path = reach_path(kin.shoulder, kin.wrist, np.array([0.12, -0.1, 0.04]), 0.8, 50.0)
    decision, _ = decide_path(model, arm, path.positions, start, times=path.times)
    assert len(decision.points) == len(path.times)
    assert set(decision.primitives) <= set(model.primitives)
