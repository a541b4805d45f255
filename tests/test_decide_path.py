"""Deciding along a path inside the IK tracker; the IK service can replay it."""

from __future__ import annotations

import numpy as np
import pytest

from services.decide.decider import CANDIDATES, KEPT_STEPS, Choice, Decider
from services.decide.path import (
    HOLD,
    SETTLE,
    TAIL,
    Settling,
    decide_path,
    decide_wrist_path,
)
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
    goal = np.array([0.12, 0.09 * (-arm.side.sign), 0.05])
    path = reach_path(arm, start, goal, duration, 100.0)
    return path.times, path.positions


def test_decision_names_matrix_and_every_g(arm: ArmModel, model: MotionModel) -> None:
    """One point decision per path point: the winner, its matrix, all eight g."""
    times, positions = _reach(arm)
    decision, tracked = decide_path(model, arm, positions, rest(arm.side), times=times)
    assert len(decision.points) == len(positions) == len(tracked.q)
    assert parse(Decision, decision.to_json()) == decision
    # The matrices in the order the primitives first drive the arm, so the
    # JSON is the same bytes in every process (no set order).
    assert list(decision.matrices) == list(dict.fromkeys(decision.primitives))
    held = 0
    for before, point in zip([None, *decision.points], decision.points, strict=False):
        assert point.matrix == BY_NAME[point.primitive].matrix
        assert list(point.g) == list(CANDIDATES)
        leader = max(point.g, key=lambda name: point.g[name])
        if point.g[point.primitive] < point.g[leader]:  # settling: the one in use holds
            assert before is not None and before.primitive == point.primitive
            held += 1
    assert held < len(decision.points) // 2
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
    path = reach_path(arm, start, np.array([0.12, -0.1, 0.04]), 0.8, 50.0)
    decision, _ = decide_path(model, arm, path.positions, start, times=path.times)
    assert len(decision.points) == len(path.times)
    assert set(decision.primitives) <= set(model.primitives)


def _settled(indices: list[int], left: float = 1.0) -> list[int]:
    """The primitives Settling keeps for raw winners 10 ms apart on a line."""
    times = np.arange(len(indices)) * 0.01
    positions = np.zeros((len(indices), 3))
    positions[:, 0] = np.linspace(left, 0.0, len(indices))
    settle = Settling(times, positions)
    kept: list[Choice] = []
    for k, index in enumerate(indices):
        raw = Choice(index, index, (0.0,) * len(CANDIDATES))
        kept.append(settle(k, raw, kept[-1] if kept else None))
    return [c.candidate for c in kept]


def test_settling_ignores_flips_shorter_than_settle() -> None:
    """A challenger winning less than SETTLE in a row never takes over."""
    steps = round(SETTLE / 0.01)
    flicker = [0] * 20 + ([1] * (steps - 1) + [0]) * 3 + [0] * 10
    assert _settled(flicker) == [0] * len(flicker)
    lasting = [0] * 20 + [1] * 30
    kept = _settled(lasting)
    assert kept[:20] == [0] * 20 and kept[-1] == 1
    assert kept.index(1) == 20 + steps - 1  # takes over on its SETTLE-th win


def test_settling_holds_each_primitive_and_never_returns() -> None:
    """A new primitive drives HOLD at least; a finished one does not come back."""
    raw = [0] * 20 + [1] * 30 + [0] * 30 + [2] * 30
    kept = _settled(raw)
    first_1, first_2 = kept.index(1), kept.index(2)
    assert 0 not in kept[first_1:]  # 0 handed over: it is not taken back
    assert (first_2 - first_1) * 0.01 >= HOLD - 1e-9
    assert _settled([0] * 20 + [1] * 2 + [2] * 30)[-1] == 2


def test_settling_keeps_the_primitive_near_the_goal() -> None:
    """Within TAIL of the goal no new primitive starts."""
    n = 50
    left = TAIL * 0.9  # the whole path is shorter than TAIL
    assert _settled([0] * 10 + [1] * (n - 10), left) == [0] * n


def test_deciders_for_other_steps_share_tables_and_few_are_kept(
    model: MotionModel,
) -> None:
    """Paths at ever new intervals (jittery clocks) keep memory bounded: each
    step's decider shares the step-free tables and only the last
    ``KEPT_STEPS`` are kept; a kept one decides as one built afresh."""
    base = Decider(model)
    steps = [0.01 + 1e-5 * k for k in range(1, 3 * KEPT_STEPS)]
    made = [base.with_step(step) for step in steps]
    assert len(base._steps) == KEPT_STEPS
    assert all(d.wrist is base.wrist and d.elbow is base.elbow for d in made)
    assert base.with_step(steps[-1]) is made[-1]  # kept: the same one
    fresh = Decider(model, steps[-1])
    values = (0.3, 0.05, 0.2, 0.08, 0.1)
    for previous in (None, 0):
        assert made[-1].decide(values, True, previous) == fresh.decide(
            values, True, previous
        )
    assert made[-1].log_next == fresh.log_next != base.log_next
