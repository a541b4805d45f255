"""Following a wrist path with a primitive per point."""

from __future__ import annotations

import numpy as np
import pytest

from services.ik.kernel import ChainState
from services.ik.track import PROMOTE_AFTER, track_path
from services.planner.wrist_path import reach_path
from shared.geometry import palm_normal
from shared.messages import Method
from shared.primitives import BY_NAME, MOTION_PRIMITIVES, Primitive
from shared.robot import ArmModel
from shared.robot.postures import rest

GOALS = {"right": (0.12, -0.13, 0.05), "left": (0.12, 0.13, 0.05)}


def _path(arm: ArmModel, goal: tuple[float, float, float]) -> np.ndarray:
    points = arm.fk(rest(arm.side))
    return reach_path(points.shoulder, points.wrist, np.array(goal), 1.0).positions


def _state_dependent(k: int, st: ChainState) -> Primitive:
    """A chooser that looks at the state, like the motion decision does."""
    distance = float(np.linalg.norm(st.wrist - st.shoulder))
    index = int(distance * 1000 + k) % len(MOTION_PRIMITIVES)
    return MOTION_PRIMITIVES[index]


def test_replaying_recorded_choices_gives_the_same_joint_path(arm: ArmModel) -> None:
    """Choices recorded in one run, replayed in another, give identical joints
    (the decide and ik services rely on this)."""
    path = _path(arm, GOALS[arm.side.value])
    chosen: list[str] = []

    def record(k: int, st: ChainState) -> Primitive:
        primitive = _state_dependent(k, st)
        chosen.append(primitive.name)
        return primitive

    first = track_path(arm, path, rest(arm.side), record)
    again = track_path(arm, path, rest(arm.side), lambda k, st: BY_NAME[chosen[k]])
    assert np.array_equal(first.q, again.q) and first.labels == again.labels


@pytest.mark.parametrize("method", list(Method))
def test_reaches_the_goal_within_the_limits(arm: ArmModel, method: Method) -> None:
    """Every method ends on the goal and never leaves the joint ranges."""
    path = _path(arm, GOALS[arm.side.value])
    tracked = track_path(arm, path, rest(arm.side), _state_dependent, method=method)
    assert np.linalg.norm(tracked.wrist[-1] - path[-1]) < 1e-9
    assert arm.limits.contains(tracked.q)
    np.testing.assert_allclose(
        [arm.fk(q).wrist for q in tracked.q], tracked.wrist, atol=1e-12
    )
    if method is not Method.MP:
        assert set(tracked.labels) == {method.value}


def test_full_arm_primitive_follows_the_path_closely(arm: ArmModel) -> None:
    """With every position joint active the wrist stays within 0.1 mm of the path."""
    path = _path(arm, GOALS[arm.side.value])
    tracked = track_path(
        arm, path, rest(arm.side), lambda k, st: BY_NAME["S_R E_PR W_P"]
    )
    assert np.linalg.norm(tracked.wrist - path, axis=1).max() < 1e-4


def test_straying_primitives_are_promoted_and_labelled(arm: ArmModel) -> None:
    """A one-joint primitive that leaves the path by more than 5 mm hands the point
    to the full-arm primitive, and the label says so."""
    path = _path(arm, GOALS[arm.side.value])
    tracked = track_path(arm, path, rest(arm.side), lambda k, st: BY_NAME["E_R W_P"])
    deviation = np.linalg.norm(tracked.wrist - path, axis=1)
    assert "S_R E_PR W_P" in tracked.labels
    assert deviation.max() < PROMOTE_AFTER + 0.01
    assert deviation[-1] < 1e-9


def test_grasp_primitive_turns_the_palm(arm: ArmModel) -> None:
    """S_R E_PR W_PR with a palm direction ends with the palm facing it."""
    path = _path(arm, GOALS[arm.side.value])
    palm = np.array([0.0, 0.0, 1.0])  # palm up
    tracked = track_path(
        arm, path, rest(arm.side), lambda k, st: BY_NAME["S_R E_PR W_PR"], palm=palm
    )
    facing = palm_normal(arm.rotation(tracked.q[-1], "wrist"), arm.side.sign)
    axis = arm.rotation(tracked.q[-1], "wrist")[:, 0]
    wanted = palm - (palm @ axis) * axis
    assert facing @ wanted / np.linalg.norm(wanted) > np.cos(np.radians(1.0))


def test_mp_without_a_chooser_is_refused(arm: ArmModel) -> None:
    """Method mp needs a chooser."""
    with pytest.raises(ValueError, match="chooser"):
        track_path(arm, _path(arm, GOALS[arm.side.value]), rest(arm.side), None)
