"""An operator's stop stops the follower too (``bridge --follow``).

A real router, a bridge service and its follower in this process, the
simulated NAO over libqi, and another libqi session as the operator, who
stops the arm the documented way (``ALMotion.killTasksUsingResources``).
"""

from __future__ import annotations

import contextlib
import logging
import threading
import time
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest

from armplan.launch import Launcher, free_endpoint
from bridge.follower import TrajectoryFollower
from bridge.minimum_jerk import minimum_jerk_trajectory
from bridge.naoqi_client import NaoqiClient
from bridge.robot_bridge import RobotBridge
from bridge.service import BridgeService
from bridge.sim import SimProcess
from bridge.sim.log import read_log
from shared.bus import Bus, BusConfig, load_config
from shared.bus.routes import TRAJECTORY_TOPIC
from shared.bus.topics import BRIDGE_OUTCOME_TOPIC, BRIDGE_REPORT_TOPIC
from shared.libqi import qi
from shared.messages import ExecutionOutcome, Trajectory
from shared.robot.postures import forward, rest


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


def _reach(there: list[float], seconds: float) -> Trajectory:
    """Rest -> ``there`` -> rest, minimum jerk, ``seconds`` each way."""
    return minimum_jerk_trajectory(
        "right", [rest("right"), there, rest("right")], [seconds, seconds]
    )


def _wait(what: str, done: Any, within: float = 20.0) -> None:
    deadline = time.monotonic() + within
    while not done():
        assert time.monotonic() < deadline, f"{what}: not within {within:g} s"
        time.sleep(0.02)


def _calls(log: Path, method: str) -> list[dict[str, Any]]:
    return [
        e for e in read_log(log) if e["event"] == "call" and e.get("method") == method
    ]


@pytest.fixture
def following(tmp_path: Path) -> Iterator[tuple[Bus, TrajectoryFollower, SimProcess]]:
    """Ports free now (fixed ones were taken, now and then, by another
    process's outgoing connection: the router exited while starting)."""
    robot = f"tcp://127.0.0.1:{free_endpoint().rsplit(':', 1)[1]}"
    config = load_config(endpoints=(free_endpoint(),))
    with following_stack(config, robot, tmp_path) as stack:
        yield stack


@contextlib.contextmanager
def following_stack(
    config: BusConfig, robot: str, folder: Path
) -> Iterator[tuple[Bus, TrajectoryFollower, SimProcess]]:
    """A router on ``config``, the sim at ``robot``, a bridge following in
    this process; their logs in ``folder``."""
    sim = SimProcess(listen=robot, log_path=folder / "sim.jsonl")
    with (
        (folder / "router.log").open("w") as router_log,
        Launcher(config, [], log=router_log),
    ):
        sim.start()
        try:
            with Bus.connect(config, wait=10.0) as bus:
                service = BridgeService(bus, RobotBridge(NaoqiClient(sim.url)))
                follower = TrajectoryFollower(service).start()
                try:
                    yield bus, follower, sim
                finally:
                    follower.stop()
        finally:
            sim.stop()


def test_a_stop_during_the_first_of_three_drops_the_two_waiting(
    following: tuple[Bus, TrajectoryFollower, SimProcess],
) -> None:
    """Three trajectories published; the operator kills the arm's tasks
    during the first: the follower played the other two at once (the arm
    moved again 0.16 s after the stop, for 6 s). Now both are dropped and
    logged, the arm stays still, and a trajectory published after the stop
    plays."""
    bus, follower, sim = following
    assert sim.log_path is not None
    records = Records()
    logging.getLogger("armplan.bridge").addHandler(records)
    heard: dict[str, list[bytes]] = {BRIDGE_OUTCOME_TOPIC: [], BRIDGE_REPORT_TOPIC: []}
    listeners = [
        bus.session.declare_subscriber(
            bus.key(path), lambda s, path=path: heard[path].append(s.payload.to_bytes())
        )
        for path in heard
    ]
    session = qi.Session()
    session.connect(sim.url)
    try:
        for seconds in (1.0, 0.8, 0.7):  # the first: 2 s, time to stop it
            bus.publish(TRAJECTORY_TOPIC, _reach(forward("right"), seconds))
        _wait("the first played", lambda: _calls(sim.log_path, "angleInterpolation"))
        time.sleep(0.4)  # mid-way through the first
        session.service("ALMotion").killTasksUsingResources(["RArm"])
        _wait("the stop seen", lambda: records.matching("robot stopped the move"))
        killed = len(_calls(sim.log_path, "angleInterpolation"))
        assert killed == 1  # the first only, no approach: the arm was at rest
        assert follower.dropped == 2
        assert "dropped the 2 trajectories" in records.matching("dropped")[0]
        # published after the stop: played, and the only one played since
        bus.publish(TRAJECTORY_TOPIC, _reach(forward("right"), 0.5))
        _wait("the one published after the stop", lambda: follower.played == 1)
        _wait("its outcome", lambda: len(heard[BRIDGE_OUTCOME_TOPIC]) == 2)
    finally:
        for listener in listeners:
            listener.undeclare()
        session.close()
        logging.getLogger("armplan.bridge").removeHandler(records)
    # the stop is on the bus too (it published nothing: no report, no outcome)
    stop, done = (
        ExecutionOutcome.model_validate_json(m) for m in heard[BRIDGE_OUTCOME_TOPIC]
    )
    print(f"\n{stop.model_dump_json()}")
    assert (stop.outcome, stop.error_kind, stop.phase) == (
        "stopped",
        "robot_state",
        "trajectory",
    )
    assert stop.played is not None and 0.2 < stop.played < 1.5
    assert stop.phase_duration == pytest.approx(2.0, abs=0.05)
    assert done.outcome == "completed" and done.message is None
    assert len(heard[BRIDGE_REPORT_TOPIC]) == 1  # of the completed one only
    log = read_log(sim.log_path)
    kill = next(
        i for i, e in enumerate(log) if e.get("method") == "killTasksUsingResources"
    )
    after = [e["duration"] for e in log[kill:] if e["event"] == "motion"]
    print("\nmotions after the stop, their durations [s]:", after)
    # an approach from where the arm stopped, then the 1 s trajectory only
    assert 1 <= len(after) <= 2 and abs(after[-1] - 1.0) < 0.05
