"""Following a wrist path with a primitive per point."""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
import pytest

from services.ik.kernel import ChainState
from services.ik.track import JUMP, track_path
from services.planner.wrist_path import reach_path
from shared.geometry import palm_normal
from shared.geometry.palm import roll_error
from shared.messages import Method
from shared.primitives import BY_NAME, MOTION_PRIMITIVES, Primitive
from shared.robot import ArmModel
from shared.robot.postures import rest

GOALS = {"right": (0.12, -0.13, 0.05), "left": (0.12, 0.13, 0.05)}


def _path(arm: ArmModel, goal: tuple[float, float, float]) -> np.ndarray:
    return reach_path(arm, rest(arm.side), np.array(goal), 1.0).positions


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
    assert np.linalg.norm(tracked.wrist[-1] - path[-1]) < 1e-6
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


def test_locked_joints_help_only_where_the_primitive_cannot(arm: ArmModel) -> None:
    """A one-joint primitive (E_R W_P) keeps the wrist on any path: the locked
    joints do what ElbowRoll cannot. On a path ElbowRoll alone makes, they
    stay nearly still (with every joint free they would take ~18 %)."""
    primitive = BY_NAME["E_R W_P"]
    path = _path(arm, GOALS[arm.side.value])
    tracked = track_path(arm, path, rest(arm.side), lambda k, st: primitive)
    assert np.linalg.norm(tracked.wrist - path, axis=1).max() < 1e-4
    assert set(tracked.labels) == {"E_R W_P"}
    bend = arm.side.sign  # ElbowRoll bends the elbow this way
    start = rest(arm.side).copy()
    start[3] = (arm.limits.lower if bend > 0 else arm.limits.upper)[3] + bend * 0.3
    postures = [start + np.eye(5)[3] * bend * 0.8 * s for s in np.linspace(0, 1, 101)]
    own = np.array([arm.fk(q).wrist for q in postures])
    alone = track_path(arm, own, start, lambda k, st: primitive)
    travel = np.abs(np.diff(alone.q, axis=0)).sum(axis=0)
    assert np.linalg.norm(alone.wrist - own, axis=1).max() < 1e-4
    assert travel[[0, 1, 2, 4]].sum() < 0.03 * travel[3]


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


@pytest.mark.parametrize("method", [Method.MP, Method.LEAST_NORM, Method.SINGLE])
def test_the_palm_turns_with_the_hand(arm: ArmModel, method: Method) -> None:
    """Along the path the roll still to make is the start's lack of roll times
    the part of the path still ahead (within 0.02 rad), and none at the goal:
    the palm neither turns ahead of the hand nor lags it."""
    path = _path(arm, GOALS[arm.side.value])
    palm = np.array([0.0, 0.0, 1.0])  # palm up: about 0.47 rad to turn
    tracked = track_path(
        arm,
        path,
        rest(arm.side),
        lambda k, st: BY_NAME["S_R E_PR W_PR"],
        method=method,
        palm=palm,
    )
    steps = np.r_[0.0, np.linalg.norm(np.diff(path, axis=0), axis=1)]
    ahead = 1.0 - np.cumsum(steps) / steps.sum()
    rotations = [arm.rotation(q, "wrist") for q in tracked.q]
    roll = np.array([roll_error(r, arm.side.sign, palm) for r in rotations])
    assert abs(roll[0]) > 0.4
    np.testing.assert_allclose(roll, ahead * roll[0], atol=0.02)
    assert abs(roll[-1]) < 1e-6


def _always(primitive: Primitive) -> Callable[[int, ChainState], Primitive]:
    return lambda k, st: primitive


def test_a_reachable_palm_is_met_at_the_goal_without_a_jump(arm: ArmModel) -> None:
    """Targets and palms of seeded postures (so both can be met): whatever the
    primitive, the path ends on the goal with the palm met, and no joint
    jumps at the last point (more than ``JUMP``): where only a jump would
    meet it, the movement goes in joint space instead. (Before, the goal's
    convergence handed over to the full-arm primitive without the palm: some
    ended 0.2-0.5 rad of roll short, after a jump of up to 0.13 rad.)"""
    rng = np.random.default_rng(1)
    detours = 0
    for _ in range(40):
        posture = rng.uniform(arm.limits.lower + 0.3, arm.limits.upper - 0.3)
        goal = arm.fk(posture).wrist
        palm = palm_normal(arm.rotation(posture, "wrist"), arm.side.sign)
        path = reach_path(arm, rest(arm.side), goal, 1.0).positions
        for name in ("S_R E_P W_P", "E_R W_P", "S_R E_PR W_P"):
            tracked = track_path(
                arm, path, rest(arm.side), _always(BY_NAME[name]), palm=palm
            )
            end = arm.rotation(tracked.q[-1], "wrist")
            assert abs(roll_error(end, arm.side.sign, palm)) < 1e-4
            assert np.linalg.norm(tracked.wrist[-1] - goal) < 1e-4  # solve's
            assert np.abs(tracked.q[-1] - tracked.q[-2]).max() <= JUMP
            detours += tracked.detour_from is not None
    assert detours > 0


def test_mp_without_a_chooser_is_refused(arm: ArmModel) -> None:
    """Method mp needs a chooser."""
    with pytest.raises(ValueError, match="chooser"):
        track_path(arm, _path(arm, GOALS[arm.side.value]), rest(arm.side), None)


def _front_targets(arm: ArmModel, n: int) -> list[np.ndarray]:
    """Targets in front of the robot (x > 5 cm) whose postures keep every joint
    at least 0.3 rad inside its range, seeded."""
    rng = np.random.default_rng(5)
    out: list[np.ndarray] = []
    while len(out) < n:
        posture = rng.uniform(arm.limits.lower + 0.3, arm.limits.upper - 0.3)
        wrist = arm.fk(posture).wrist
        if wrist[0] > 0.05 and -0.05 < wrist[2] < 0.2:
            out.append(wrist)
    return out


def test_reaches_in_front_give_smooth_joint_paths(arm: ArmModel) -> None:
    """One GPM step per point and gains that follow the hand: no sawtooth. The
    third differences of the joint path stay tiny (a 0.1 mrad sawtooth at
    100 Hz alone would be ~3000 rad/s^3 of jerk) unless a joint touches its
    limit on the way: the task must then drive it onto the limit, a genuine
    corner that the timing takes from rest. Most reaches touch none."""
    smooth = 0
    for goal in _front_targets(arm, 10):
        tracked = track_path(
            arm,
            _path(arm, tuple(goal)),
            rest(arm.side),
            lambda k, st: BY_NAME["S_R E_PR W_P"],
        )
        rough = np.abs(np.diff(tracked.q, 3, axis=0)).max() >= 2e-3
        touches = np.any(
            (tracked.q <= arm.limits.lower + 1e-3)
            | (tracked.q >= arm.limits.upper - 1e-3)
        )
        assert not rough or touches or tracked.detour_from is not None
        smooth += not rough
    assert smooth >= 8


@pytest.mark.parametrize("method", [Method.LEAST_NORM, Method.SINGLE])
def test_a_path_sampled_finer_gives_the_same_joint_path(
    arm: ArmModel, method: Method
) -> None:
    """A reach sampled ten times as densely (a slow path at the same rate,
    here 2 s at 1000 Hz against 100 Hz) passes through the same postures:
    self-motion goes with the path, not its samples (within 5 mrad: 0.4
    and 2.2 mrad). (Counted per sample, ``single`` made ten times the
    self-motion on the finer path, which ended up to 0.88 rad elsewhere.)"""
    goal = np.array(GOALS[arm.side.value])
    coarse, fine = (
        track_path(
            arm,
            reach_path(arm, rest(arm.side), goal, 2.0, rate).positions,
            rest(arm.side),
            None,
            method=method,
        ).q
        for rate in (100.0, 1000.0)
    )
    assert len(fine) == 10 * (len(coarse) - 1) + 1
    assert np.abs(fine[::10] - coarse).max() < 5e-3


def test_unfollowable_paths_become_one_joint_space_move() -> None:
    """A path the arm cannot follow within its limits: the whole movement goes in
    joint space from the start to the goal posture, and still ends on the goal."""
    arm = _arm_right()
    goal = (-0.0584, -0.2103, 0.1592)  # up and behind: the arc runs into the limits
    path = _path(arm, goal)
    tracked = track_path(
        arm, path, rest(arm.side), lambda k, st: BY_NAME["S_R E_PR W_P"]
    )
    assert tracked.detour_from == 0
    assert np.array_equal(tracked.q[0], rest(arm.side))
    assert np.linalg.norm(tracked.wrist[-1] - np.array(goal)) < 1e-4
    steps = np.diff(tracked.q, axis=0)
    directions = steps / np.linalg.norm(steps, axis=1, keepdims=True).clip(1e-12)
    assert np.allclose(directions[1:-1], directions[len(directions) // 2], atol=1e-9)
    assert set(tracked.labels) == {"S_R E_PR W_P"}


def _arm_right() -> ArmModel:
    from shared.robot import load_arm

    return load_arm("right")
