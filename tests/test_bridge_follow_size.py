"""The follower drops a publication over the bus's ``max_payload`` unread.

``bridge/execute`` refuses such a payload ``payload_too_large``; the
follower (``bridge --follow``) read and parsed it whatever its size: one
204 MB trajectory published on ``plan/trajectory`` held 2.7 GB of the
bridge's memory, and sixteen could wait. A real router, a bridge service
and its follower in this process, the simulated NAO over libqi; the bus's
``max_payload`` is set between the sizes of two valid trajectories.
"""

from __future__ import annotations

import dataclasses
import logging
import threading
import time
from collections.abc import Callable, Iterator
from pathlib import Path

import pytest
from test_bridge_follow_stop import following_stack

from armplan.launch import free_endpoint
from bridge.follower import TrajectoryFollower
from bridge.minimum_jerk import minimum_jerk_trajectory
from bridge.sim import SimProcess
from bridge.sim.log import read_log
from shared.bus import Bus, load_config
from shared.bus.routes import TRAJECTORY_TOPIC
from shared.messages import Trajectory
from shared.robot.postures import forward, rest


def _reach(seconds: float) -> Trajectory:
    """Rest -> forward -> rest, minimum jerk, ``seconds`` each way."""
    there = forward("right")
    return minimum_jerk_trajectory(
        "right", [rest("right"), there, rest("right")], [seconds, seconds]
    )


SMALL, LARGE = _reach(0.4), _reach(3.0)
#: Between the two trajectories' JSON sizes [bytes].
LIMIT = (len(SMALL.to_json()) + len(LARGE.to_json())) // 2


class Records(logging.Handler):
    """The messages logged on ``armplan.bridge`` while it is attached."""

    def __init__(self) -> None:
        super().__init__(logging.INFO)
        self.messages: list[str] = []
        self._lock = threading.Lock()

    def emit(self, record: logging.LogRecord) -> None:
        with self._lock:
            self.messages.append(record.getMessage())

    def matching(self, words: str) -> list[str]:
        with self._lock:
            return [m for m in self.messages if words in m]


def _wait(what: str, done: Callable[[], object], within: float = 20.0) -> None:
    deadline = time.monotonic() + within
    while not done():
        assert time.monotonic() < deadline, f"{what}: not within {within:g} s"
        time.sleep(0.02)


@pytest.fixture
def following(tmp_path: Path) -> Iterator[tuple[Bus, TrajectoryFollower, SimProcess]]:
    config = dataclasses.replace(
        load_config(endpoints=(free_endpoint(),)), max_payload=LIMIT
    )
    robot = free_endpoint().replace("tcp/", "tcp://")
    with following_stack(config, robot, tmp_path) as stack:
        yield stack


def test_a_trajectory_over_max_payload_is_dropped_and_the_next_plays(
    following: tuple[Bus, TrajectoryFollower, SimProcess],
) -> None:
    """The large one is dropped with a warning naming its size and the
    limit, never sent to the robot; the small one published after it plays."""
    bus, follower, sim = following
    assert sim.log_path is not None
    assert len(SMALL.to_json()) < LIMIT < len(LARGE.to_json())
    records = Records()
    logging.getLogger("armplan.bridge").addHandler(records)
    try:
        bus.publish(TRAJECTORY_TOPIC, LARGE)
        _wait("the drop logged", lambda: records.matching("over the bus's max_payload"))
        bus.publish(TRAJECTORY_TOPIC, SMALL)
        _wait("the small one played", lambda: follower.played == 1)
    finally:
        logging.getLogger("armplan.bridge").removeHandler(records)
    (warning,) = records.matching("over the bus's max_payload")
    assert f"{len(LARGE.to_json())} bytes" in warning and str(LIMIT) in warning
    played = [
        e
        for e in read_log(sim.log_path)
        if e["event"] == "call" and e.get("method") == "angleInterpolation"
    ]
    assert len(played) == 1  # the small one only
