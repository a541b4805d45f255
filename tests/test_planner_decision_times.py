"""Each reach's decision on the trajectory's clock: real plans, in process.

A decision's own times are its wrist path's (each reach's from 0, at the
nominal pace); ``trajectory_times`` must say when the planned trajectory is
at each of its points, which the trajectory's wrist there shows.
"""

from __future__ import annotations

import numpy as np
import pytest

from services.planner.pipeline import PlanResult, plan
from services.planner.wrist_path import reach_path
from shared.messages import PlanRequest, WristPath
from shared.robot import load_arm
from shared.robot.postures import rest

#: Four reaches: a rest after the first and the third, none after the second.
TASK = {
    "targets": [
        {"position": (0.14, -0.10, 0.06), "dwell": 0.5},
        {"position": (0.10, -0.17, 0.02), "dwell": 0.0},
        {"position": (0.11, -0.07, 0.01), "dwell": 0.3},
        {"position": (0.13, -0.07, 0.09)},
    ]
}
#: Farthest the trajectory's wrist may be from a decision point's when the
#: trajectory passes it [m] (0.11 mm measured on the demo's task; the next
#: point is millimetres on).
AT_POINT = 5e-4


def wrist_at(result: PlanResult, times: list[float]) -> np.ndarray:
    """The planned trajectory's wrist [m], (n, 3), at ``times`` [s]."""
    t = np.array(result.trajectory.times) - result.trajectory.times[0]
    wrist = np.array(result.trajectory.wrist_path)
    return np.array([np.interp(times, t, wrist[:, i]) for i in range(3)]).T


@pytest.mark.parametrize("fastest", [False, True], ids=["human-pace", "fastest"])
def test_every_decision_point_is_where_the_trajectory_passes_it(
    fastest: bool,
) -> None:
    """The trajectory's wrist at each point's trajectory time is the joint
    path's there; the reaches follow each other without overlap, from the
    trajectory's start to its end; the plan's trajectory has no point times."""
    result = plan(PlanRequest.model_validate(TASK | {"fastest": fastest}))
    assert len(result.decisions) == 4
    joined: list[float] = []
    for k, (decision, path) in enumerate(
        zip(result.decisions, result.joint_paths, strict=True)
    ):
        times = decision.trajectory_times
        assert times is not None and len(times) == len(decision.times)
        off = np.linalg.norm(wrist_at(result, times) - np.array(path.wrist), axis=1)
        assert off.max() < AT_POINT, f"reach {k}: {off.max() * 1e3:.3f} mm"
        joined += times
    assert joined[0] == 0.0
    assert np.all(np.diff(joined) >= 0.0)
    assert joined[-1] == pytest.approx(result.trajectory.duration)
    first, second, third, _ = result.decisions
    assert second.trajectory_times[0] == pytest.approx(  # type: ignore[index]
        first.trajectory_times[-1] + 0.5  # type: ignore[index]
    )
    assert third.trajectory_times[0] == second.trajectory_times[-1]  # type: ignore[index]
    assert result.trajectory.point_times is None
    assert "point_times" not in result.trajectory.to_json()


def test_a_reach_that_does_not_move_is_decided_before_the_hand_closes() -> None:
    """Resting 0.2 s at A, then a second target at A closing the hand: the
    second reach does not move, so all its points are where the arm stands
    when the first rest ends, before the hand moves (they came after the
    hand had closed, at the trajectory's end)."""
    a = (0.12, -0.13, 0.05)
    task = {
        "targets": [{"position": a, "dwell": 0.2}, {"position": a, "hand": "close"}]
    }
    result = plan(PlanRequest.model_validate(task))
    first, second = (d.trajectory_times for d in result.decisions)
    assert first is not None and second is not None
    hand = np.array(result.trajectory.hand)
    closing = float(result.trajectory.times[np.flatnonzero(np.diff(hand))[0]])
    arrived = first[-1] + 0.2
    assert second == pytest.approx([arrived] * len(second))
    assert closing == pytest.approx(arrived)
    assert result.trajectory.duration > arrived + 0.3  # the hand's time after


def test_a_target_at_the_resting_wrist_is_decided_at_the_start() -> None:
    """One target where the resting arm's wrist already is, closing the hand:
    its points at 0, not when the hand has closed."""
    arm = load_arm("right")
    wrist = tuple(float(x) for x in arm.fk(rest(arm.side)).wrist)
    task = {"targets": [{"position": wrist, "hand": "close"}]}
    result = plan(PlanRequest.model_validate(task))
    (decision,) = result.decisions
    assert decision.trajectory_times == [0.0] * len(decision.times)
    assert result.trajectory.duration > 0.3


def test_a_timed_wrist_path_s_decision_is_on_the_path_s_own_clock() -> None:
    """A wrist path played at its own times (at 50 Hz, so the decision is
    made on the tracker's even 100 Hz grid): each point at its own time (a
    path's times start at 0, the movement's start: one from 2 s is refused)."""
    arm = load_arm("right")
    goal = np.array((0.12, -0.10, 0.05))
    path = reach_path(arm, rest(arm.side), goal, 1.5, rate=50.0)
    given = WristPath(
        arm=arm.side,
        times=path.times.tolist(),
        positions=[tuple(p) for p in path.positions.tolist()],
    )
    result = plan(PlanRequest(wrist_path=given))
    (decision,) = result.decisions
    assert decision.trajectory_times == pytest.approx(decision.times, abs=1e-12)
    assert decision.times != given.times  # decided on the even grid
