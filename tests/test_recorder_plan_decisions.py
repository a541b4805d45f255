"""A task of several targets planned through the real services and recorded:
the derived ``/decision`` channel follows the planned arm in time.

Each reach's decision is made on its wrist path's own clock (from 0); the
recording must still place its points when the trajectory passes them, one
reach after the other, as ``/tf/planned`` places the trajectory's samples.
"""

from __future__ import annotations

import subprocess
import time
from collections import defaultdict
from collections.abc import Iterator
from itertools import pairwise
from typing import NamedTuple

import pytest

from armplan.launch import Launcher, free_endpoint
from services.recorder import RecorderOptions
from services.recorder.service import Recorder
from shared.bus import Bus, load_config
from shared.bus.routes import PLAN
from shared.messages import Decision, PlanRequest, Trajectory
from shared.recording import read_records
from shared.recording.foxglove import DECISION_TOPIC, PLANNED_TF_TOPIC, PrimitiveSample

#: Five reaches; rests after some, none after the others (nor after the last).
TASK = PlanRequest.model_validate(
    {
        "targets": [
            {"position": (0.14, -0.10, 0.06), "dwell": 0.4},
            {"position": (0.10, -0.17, 0.02), "dwell": 0.0},
            {"position": (0.11, -0.07, 0.01), "dwell": 0.3},
            {"position": (0.13, -0.07, 0.09), "dwell": 0.0},
            {"position": (0.06, -0.16, 0.22)},
        ]
    }
)
#: Longest wait for the planner's publications after its answer [s].
SETTLE = 0.5
#: Farthest a decision's first point may be from the trajectory's first
#: sample, and its last from the last sample [ns]: the decisions are
#: published right after the trajectory (measured: 5 ms after it).
NEAR = 50_000_000


class Session(NamedTuple):
    """What the recording holds of the plan.

    Attributes:
        trajectory: The plan's answer.
        decisions: The recorded decisions with their log times [ns], in order.
        planned: Log times of ``/tf/planned`` [ns], in file order.
        points: ``/decision`` (log time [ns], sample), in file order.
    """

    trajectory: Trajectory
    decisions: list[tuple[int, Decision]]
    planned: list[int]
    points: list[tuple[int, PrimitiveSample]]


@pytest.fixture(scope="module")
def session(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Session]:
    """The planner, its stage services and a recorder on one router."""
    out = tmp_path_factory.mktemp("plan") / "plan.mcap"
    config = load_config(endpoints=(free_endpoint(),))
    names = ["decide", "ik", "timing", "planner"]
    with (
        Launcher(config, names, log=subprocess.DEVNULL),
        Bus.connect(config) as bus,
        Recorder(bus, RecorderOptions(output=out)),
    ):
        assert bus.wait_alive(["recorder"], 5.0) == []
        trajectory = bus.call(PLAN, TASK)
        time.sleep(SETTLE)
    records = list(read_records(out))
    yield Session(
        trajectory,
        [
            (r.log_time, Decision.model_validate(r.data))
            for r in records
            if r.topic.endswith("/plan/decision")
        ],
        [r.log_time for r in records if r.topic == PLANNED_TF_TOPIC],
        [
            (r.log_time, PrimitiveSample.model_validate(r.data))
            for r in records
            if r.topic == DECISION_TOPIC
        ],
    )


def test_the_decision_points_follow_each_other_over_the_whole_trajectory(
    session: Session,
) -> None:
    """A point per path point of the five decisions, their log times never
    going back, from the trajectory's first sample to its last (the arm
    arrives at the last target as it ends)."""
    assert len(session.decisions) == len(TASK.targets)
    assert len(session.points) == sum(len(d.times) for _, d in session.decisions)
    stamps = [stamp for stamp, _ in session.points]
    assert all(b >= a for a, b in pairwise(stamps))
    assert len(session.planned) == len(session.trajectory.times)
    assert abs(stamps[0] - session.planned[0]) < NEAR
    assert abs(stamps[-1] - session.planned[-1]) < NEAR
    span = (stamps[-1] - stamps[0]) * 1e-9
    assert span == pytest.approx(session.trajectory.duration, abs=0.01)


def test_each_recorded_moment_has_one_winner(session: Session) -> None:
    """No two reaches' points overlap in time (each reach's end before the
    next one's start), and no log time holds two winners."""
    points = iter(session.points)
    spans = []
    for _, decision in session.decisions:
        stamps = [next(points)[0] for _ in decision.times]
        spans.append((stamps[0], stamps[-1]))
    for k, (before, after) in enumerate(pairwise(spans)):
        assert before[1] <= after[0], f"reach {k + 1} starts before reach {k} ends"
    at: dict[int, set[int]] = defaultdict(set)
    for stamp, sample in session.points:
        at[stamp].add(sample.index)
    assert all(len(winners) == 1 for winners in at.values())


def test_a_point_is_at_its_decision_s_arrival_plus_its_trajectory_time(
    session: Session,
) -> None:
    """The decisions arrive after the trajectory, carrying when it passes
    each point; the points of each are placed by those times."""
    points = iter(session.points)
    for k, (arrival, decision) in enumerate(session.decisions):
        assert decision.trajectory_times is not None, f"reach {k}"
        assert arrival >= session.planned[0]
        stamps = [next(points)[0] for _ in decision.times]
        expected = [arrival + round(t * 1e9) for t in decision.trajectory_times]
        assert stamps == expected, f"reach {k}"


def test_the_answer_has_no_point_times(session: Session) -> None:
    """The trajectory the planner answers is the SPEC's: no point times."""
    assert session.trajectory.point_times is None
    assert "point_times" not in session.trajectory.to_json()
