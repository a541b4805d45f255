"""Hand actions at reach targets: the trajectory's hand channel (planner side)."""

from __future__ import annotations

import json

import numpy as np
import pytest

from armplan.cli.main import main
from services.planner.pipeline import plan
from services.planner.timing_stage import timing
from services.timing import check_limits
from services.timing.hand import hand_duration
from shared.messages import PlanRequest, ReachTarget, TimingRequest, Trajectory, parse
from shared.robot import load_arm
from shared.robot.hand import hand_motion_limits

GRASP = (0.12, -0.10, 0.05)
PLACE = (0.10, -0.14, 0.0)


def _plan(*targets: dict, **options: object) -> Trajectory:  # type: ignore[type-arg]
    request = parse(PlanRequest, {"targets": list(targets), **options})
    return plan(request).trajectory


def _still(trajectory: Trajectory) -> np.ndarray:
    """Whether the arm is at rest over each step between samples, shape (n - 1,)."""
    q = np.asarray(trajectory.positions)
    return np.abs(np.diff(q, axis=0)).max(axis=1) < 1e-12


def test_the_hand_closes_and_opens_during_the_dwells_within_its_limits() -> None:
    """Close at the grasp, open at the place: open (1) before the close, shut (0)
    from the first dwell to the second, open at the end; it moves only while
    the arm rests, once in each dwell, and keeps its range, speed, acceleration
    and jerk limits (divided differences)."""
    trajectory = _plan(
        {"position": GRASP, "dwell": 0.6, "hand": "close"},
        {"position": PLACE, "dwell": 0.6, "hand": "open"},
    )
    t, hand = np.asarray(trajectory.times), np.asarray(trajectory.hand)
    assert hand[0] == 1.0 and hand[-1] == 1.0
    check_limits(t, hand[:, None], hand_motion_limits("right"))
    steps = np.abs(np.diff(hand)) > 0.0
    assert np.all(_still(trajectory)[steps])  # the arm rests while the hand moves
    runs = np.flatnonzero(np.diff(steps.astype(int)))  # starts and ends of moves
    assert len(runs) == 4
    closed = slice(runs[1] + 1, runs[2] + 1)
    assert np.all(hand[closed] == 0.0)
    assert (~_still(trajectory))[closed].any()  # carried shut from grasp to place
    arm = load_arm("right")
    for (first, last), at in (((runs[0], runs[1]), GRASP), ((runs[2], runs[3]), PLACE)):
        for q in trajectory.positions[first : last + 2]:  # at the target throughout
            assert np.linalg.norm(arm.fk(np.array(q)).wrist - at) < 1e-3


def test_a_short_dwell_is_lengthened_to_the_hands_time() -> None:
    """A close with no dwell holds the arm as long as the hand needs (0.45 s at
    100 Hz, the shortest minimum-jerk close within its limits), and the arm
    moves as with that dwell asked for and no hand."""
    limits = hand_motion_limits("right")
    needed = hand_duration(1.0, limits, 0.01)
    assert needed == pytest.approx(0.45)
    with_hand = _plan({"position": GRASP, "hand": "close"}, {"position": PLACE})
    asked = _plan({"position": GRASP, "dwell": needed}, {"position": PLACE})
    assert asked.hand is None
    assert with_hand.times == asked.times
    assert with_hand.positions == asked.positions
    hand = np.asarray(with_hand.hand)
    t = np.asarray(with_hand.times)
    began = t[np.argmax(hand < 1.0) - 1]
    ended = t[np.argmax(hand == 0.0)]
    assert ended - began == pytest.approx(needed)


def test_an_action_the_hand_has_done_does_not_move_it_or_lengthen_the_dwell() -> None:
    """Close, then close again at a target with no dwell: the hand stays shut
    and the second target's dwell is not lengthened."""
    twice = _plan(
        {"position": GRASP, "dwell": 0.5, "hand": "close"},
        {"position": PLACE, "hand": "close"},
    )
    once = _plan(
        {"position": GRASP, "dwell": 0.5, "hand": "close"}, {"position": PLACE}
    )
    assert twice.positions == once.positions
    assert twice.hand == once.hand and twice.hand[-1] == 0.0


def test_without_a_hand_action_the_json_has_no_hand() -> None:
    """No action: no ``hand`` key in the trajectory's, target's or timing
    segment's JSON (their bytes as before the hand existed); with one, the
    key is there and survives the wire."""
    trajectory = _plan({"position": GRASP})
    for key in ("hand", "hand_velocities", "hand_accelerations"):
        assert key not in json.loads(trajectory.to_json())
        assert key not in trajectory.model_dump()
    assert "hand" not in ReachTarget(position=GRASP).to_json()
    grasp = _plan({"position": GRASP, "hand": "close"})
    assert json.loads(grasp.to_json())["hand"] == grasp.hand
    assert parse(Trajectory, grasp.to_json()) == grasp


def test_the_hand_carries_its_planned_speed_and_acceleration() -> None:
    """The trajectory carries the hand's rate [1/s] and its rate [1/s^2] as
    planned (exact minimum jerk): they match the channel's central
    differences away from the moves' ends, are 0 wherever the hand rests,
    peak at the profile's 15/8 and 10/sqrt(3) of a full move in 0.45 s, and
    survive the wire; given without a hand, or one per sample too few, a
    trajectory is refused."""
    trajectory = _plan(
        {"position": GRASP, "hand": "close"}, {"position": PLACE, "hand": "open"}
    )
    t, hand = np.asarray(trajectory.times), np.asarray(trajectory.hand)
    speed = np.asarray(trajectory.hand_velocities)
    change = np.asarray(trajectory.hand_accelerations)
    still = np.concatenate([[True], np.diff(hand) == 0.0, [True]])
    resting = still[:-1] & still[1:]  # equal to both neighbours
    assert resting.sum() > len(t) // 2
    assert np.all(speed[resting] == 0.0) and np.all(change[resting] == 0.0)
    inner = np.convolve(~resting, np.ones(5), "same") == 5  # 2 samples off a rest
    assert inner.sum() > 50
    assert np.abs(np.gradient(hand, t) - speed)[inner].max() < 0.01
    assert np.abs(np.gradient(speed, t) - change)[inner].max() < 0.2
    assert np.abs(speed).max() == pytest.approx(1.875 / 0.45, rel=1e-3)
    assert np.abs(change).max() == pytest.approx(10 / np.sqrt(3) / 0.45**2, rel=2e-2)
    assert parse(Trajectory, trajectory.to_json()) == trajectory
    no_hand = trajectory.model_dump() | {"hand": None}
    with pytest.raises(ValueError, match="hand_velocities is given without hand"):
        Trajectory.model_validate(no_hand)
    short = trajectory.model_dump() | {"hand_accelerations": change[1:].tolist()}
    with pytest.raises(ValueError, match="hand_accelerations has"):
        Trajectory.model_validate(short)


def test_the_timing_stage_over_the_wire_gives_the_same_hand() -> None:
    """The timing request of a task with a hand action, sent as JSON (as to
    the timing service), gives the trajectory planned in-process."""
    from services.planner.pipeline import track_movement
    from services.planner.reach_path import reach_wrist_path
    from services.planner.stages import LocalStages
    from shared.messages import Method, TimingSegment
    from shared.robot.postures import rest

    arm = load_arm("right")
    target = ReachTarget(position=GRASP, hand="close")  # type: ignore[arg-type]
    start = rest(arm.side)
    path = reach_wrist_path(arm, start, target)
    joint_path, _ = track_movement(LocalStages(), path, start, Method.MP, None)
    request = TimingRequest(
        segments=[TimingSegment(joint_path=joint_path, duration=0.8, hand=target.hand)]
    )
    assert '"hand":"close"' in request.to_json()
    here = timing(request)
    assert timing(parse(TimingRequest, request.to_json())) == here
    assert here.hand is not None and here.hand[-1] == 0.0


def test_the_command_line_takes_a_hand_per_target(
    capsys: pytest.CaptureFixture[str],
) -> None:
    """``--hand close`` after a target: the JSON's hand channel closes; the
    summary names the action and the lengthened dwell; ``--hand`` before any
    target, twice for one, with a word other than open/close, or with a wrist
    path is refused naming it."""
    args = ["plan", "--target", *map(str, GRASP), "--hand", "close"]
    assert main([*args, "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["hand"][0] == 1.0 and data["hand"][-1] == 0.0
    assert main(args) == 0
    out = capsys.readouterr().out
    assert "RHand [open]" in out
    assert "close at target 1 (0.45 s, its 0 s dwell lengthened to 0.45 s)" in out
    assert main(["plan", "--hand", "open", "--target", *map(str, GRASP)]) == 1
    assert "--hand comes before any --target" in capsys.readouterr().err
    assert main([*args, "--hand", "open"]) == 1
    assert "--target number 1 has --hand twice" in capsys.readouterr().err
    with pytest.raises(SystemExit):
        main([*args[:-1], "grab"])
    assert "invalid choice: 'grab'" in capsys.readouterr().err
