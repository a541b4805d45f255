"""A bridge told to stop (SIGTERM) sends no new command, and answers; a
second bridge in the namespace does not start.

Real parts: a Zenoh router and ``python -m bridge.serve`` as processes
(``armplan.launch``), the simulated NAO as its own process over libqi, and a
Zenoh client session in the test.
"""

from __future__ import annotations

import signal
import subprocess
import sys
import threading
import time
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest
import zenoh

from armplan.launch import Launcher, free_endpoint
from armplan.launch.robot import BRIDGE_GRACE, RobotStack
from bridge.minimum_jerk import minimum_jerk_trajectory
from bridge.service import STOP_LIMIT
from bridge.sim import SimProcess
from bridge.sim.log import read_log
from shared.bus import Bus, load_config
from shared.bus.robot_routes import EXECUTE
from shared.errors import ArmplanError, ServiceUnavailableError
from shared.messages import ExecuteRequest, JointState, Trajectory
from shared.robot.postures import forward, rest


class Stack:
    """A router, a bridge process, the sim and a client bus."""

    def __init__(self, robot: RobotStack, sim: SimProcess, bus: Bus) -> None:
        self.robot = robot
        self.sim = sim
        self.bus = bus
        self.states: list[JointState] = []
        self._subscriber = bus.session.declare_subscriber(
            bus.key("bridge/state"), self._on_state
        )

    def _on_state(self, sample: zenoh.Sample) -> None:
        self.states.append(JointState.model_validate_json(sample.payload.to_bytes()))

    def execute_in_background(self, trajectory: Trajectory) -> dict[str, Any]:
        """Send ``trajectory`` from a thread; the dict gets "reply" or "error"."""
        outcome: dict[str, Any] = {}

        def call() -> None:
            try:
                request = ExecuteRequest(trajectory=trajectory)
                outcome["reply"] = self.bus.call(EXECUTE, request, timeout=30.0)
            except ArmplanError as error:
                outcome["error"] = error

        outcome["thread"] = threading.Thread(target=call)
        outcome["thread"].start()
        return outcome

    def wait_for_state(self, after: float) -> None:
        """Wait until a state later than ``after`` [s, trajectory time] came."""
        deadline = time.monotonic() + 10.0
        while not any(s.time > after for s in list(self.states)):
            assert time.monotonic() < deadline, f"no state after {after} s"
            time.sleep(0.005)

    def motions(self) -> list[str]:
        """The methods of the movements the sim took, in order."""
        assert self.sim.log_path is not None
        log = read_log(self.sim.log_path)
        return [e["method"] for e in log if e["event"] == "motion"]

    def bridge_exit(self, timeout: float = 10.0) -> int | None:
        assert self.robot.bridge is not None
        deadline = time.monotonic() + timeout
        while (code := self.robot.bridge.exit_code()) is None:
            if time.monotonic() > deadline:
                return None
            time.sleep(0.05)
        return code


@pytest.fixture
def stack(tmp_path: Path) -> Iterator[Stack]:
    config = load_config(endpoints=(free_endpoint(),))
    sim = SimProcess(log_path=tmp_path / "sim.jsonl")
    sim.start()
    with (
        (tmp_path / "router.log").open("w") as router_log,
        (tmp_path / "bridge.log").open("w") as bridge_log,
        Launcher(config, [], log=router_log),
        RobotStack(config, robot=sim.url, log=bridge_log) as robot,
        Bus.connect(config) as bus,
    ):
        try:
            yield Stack(robot, sim, bus)
        finally:
            sim.stop()


def from_forward(seconds: float) -> Trajectory:
    """Arm stretched forward -> rest: from rest, a 1.4 s approach first."""
    return minimum_jerk_trajectory(
        "right", [forward("right"), rest("right")], [seconds]
    )


def test_a_bridge_stopped_during_the_approach_sends_no_trajectory(
    stack: Stack,
) -> None:
    """SIGTERM as the approach starts: the approach ends, the trajectory is
    not sent, and the caller is told so (it used to be sent after SIGTERM,
    then left unwatched, the caller told only that the bridge was gone)."""
    outcome = stack.execute_in_background(from_forward(2.0))
    stack.wait_for_state(-10.0)  # the approach's first state
    assert stack.robot.bridge is not None
    stack.robot.bridge.signal(signal.SIGTERM)
    outcome["thread"].join(15.0)
    error = outcome["error"]
    assert isinstance(error, ServiceUnavailableError), error
    assert error.reason == (
        "the bridge is stopping; the arm is at the trajectory's start; nothing "
        "of the trajectory was sent"
    )
    assert stack.bridge_exit() == 0
    assert stack.motions() == ["angleInterpolation"]  # the approach alone


def test_a_bridge_stopped_during_a_long_approach_waits_for_it(
    stack: Stack, tmp_path: Path
) -> None:
    """SIGTERM as a 3.2 s approach starts, to a 0.5 s trajectory: the stop's
    wait was bounded from the trajectory's expected end counted from the
    request (0.5 s + 2 s), so the bridge gave the request up mid-approach
    ("a request is still being served; leaving it"). Now the bound counts
    the approach: the approach ends and the caller is told nothing of the
    trajectory was sent."""
    far = [-2.0, -1.3, -2.0, 1.5, -1.8]  # 3.2 s from rest at the approach's pace
    outcome = stack.execute_in_background(
        minimum_jerk_trajectory("right", [far, far], [0.5])
    )
    stack.wait_for_state(-10.0)  # the approach's first state
    assert stack.robot.bridge is not None
    stack.robot.bridge.signal(signal.SIGTERM)
    outcome["thread"].join(15.0)
    error = outcome.get("error")
    assert isinstance(error, ServiceUnavailableError), error
    assert error.reason == (
        "the bridge is stopping; the arm is at the trajectory's start; nothing "
        "of the trajectory was sent"
    )
    assert stack.bridge_exit() == 0
    assert stack.motions() == ["angleInterpolation"]  # the approach alone
    assert "leaving it" not in (tmp_path / "bridge.log").read_text()


def test_a_bridge_stopped_during_the_trajectory_answers_at_its_end(
    stack: Stack,
) -> None:
    """SIGTERM 0.3 s into a 4 s trajectory: it plays to its end, watched, and
    the caller gets its report (it used to get service_unavailable 2 s later,
    while the arm played on unwatched); then the bridge exits 0."""
    outcome = stack.execute_in_background(from_forward(4.0))
    stack.wait_for_state(0.3)
    assert stack.robot.bridge is not None
    stack.robot.bridge.signal(signal.SIGTERM)
    outcome["thread"].join(15.0)
    assert "error" not in outcome, outcome.get("error")
    report = outcome["reply"].report
    assert report.duration >= 4.0 - 2.0 * report.sample_period
    assert max(report.tracking_rms_deg.values()) < 1.0
    assert stack.bridge_exit() == 0
    assert stack.motions() == ["angleInterpolation", "angleInterpolation"]


def test_the_stack_gives_the_bridge_time_to_watch_a_trajectory_to_its_end(
    stack: Stack,
) -> None:
    """The robot stack stopped 0.3 s into a 7 s trajectory on a robot it did
    not start: it SIGKILLed the bridge 5 s after SIGTERM, cutting off the
    bridge's own wait (up to 30 s) for the trajectory, the arm left playing
    unwatched and the caller answered by no one. Now the bridge's grace
    covers its own bound: the caller gets its report, the bridge exits 0."""
    assert BRIDGE_GRACE >= STOP_LIMIT + 2.0
    trajectory = minimum_jerk_trajectory(
        "right", [rest("right"), forward("right"), rest("right")], [3.5, 3.5]
    )
    outcome = stack.execute_in_background(trajectory)
    stack.wait_for_state(0.3)
    stack.robot.stop()  # SIGTERM; SIGKILL after the grace
    outcome["thread"].join(15.0)
    assert "error" not in outcome, outcome.get("error")
    assert outcome["reply"].report.duration >= 7.0 - 0.1
    assert stack.bridge_exit() == 0


def test_a_second_bridge_in_the_namespace_refuses_to_start(stack: Stack) -> None:
    """A bridge started while another serves the namespace exits 1 naming
    the held token, before declaring anything (both used to play every
    request, the caller getting the loser's error); the first plays on."""
    endpoint = stack.bus.config.endpoints[0]
    command = [sys.executable, "-m", "bridge.serve", "--connect", endpoint]
    second = subprocess.run(
        [*command, "--robot", stack.sim.url],
        capture_output=True,
        text=True,
        timeout=30.0,  # a second bridge that starts runs until killed here
    )
    assert second.returncode == 1
    assert (
        "service 'bridge' is already running (armplan/alive/bridge is held by "
        "another process): two bridges would both play every request on the "
        "robot; stop the other one first, or use another namespace"
    ) in second.stderr
    reply = stack.bus.call(
        EXECUTE, ExecuteRequest(trajectory=from_forward(0.5)), timeout=30.0
    )
    assert reply.approach_duration > 0.0
    assert stack.motions() == ["angleInterpolation", "angleInterpolation"]


def test_a_request_without_a_rate_plays_at_the_bridges_rate(
    tmp_path: Path,
) -> None:
    """A bridge at 50 fps (``--rate 50``), a request naming no rate: 50 fps
    frames (it used to play at the request's default 25 fps); a request
    naming 25 fps still gets 25."""
    from bridge.naoqi_client import NaoqiClient
    from bridge.robot_bridge import RobotBridge
    from bridge.service import BridgeService
    from shared.bus import ServiceHost
    from shared.bus.robot_routes import BRIDGE

    config = load_config(endpoints=(free_endpoint(),))
    sim = SimProcess(log_path=tmp_path / "sim.jsonl")
    sim.start()
    trajectory = minimum_jerk_trajectory("right", [rest("right")] * 2, [1.0])
    try:
        with (
            (tmp_path / "router.log").open("w") as router_log,
            Launcher(config, [], log=router_log),
            Bus.connect(config) as served,
            Bus.connect(config) as bus,
        ):
            robot = RobotBridge(NaoqiClient(sim.url), rate=50.0)
            service = BridgeService(served, robot)
            with ServiceHost(served, BRIDGE, service.endpoints()):
                bus.wait_alive([BRIDGE], 10.0)
                plain = ExecuteRequest(trajectory=trajectory)
                own = bus.call(EXECUTE, plain, timeout=30.0)
                asked = ExecuteRequest(trajectory=trajectory, rate=25.0)
                named = bus.call(EXECUTE, asked, timeout=30.0)
            robot.client.close()
    finally:
        sim.stop()
    assert (own.frames, named.frames) == (50, 25)
    assert ExecuteRequest.model_validate_json(
        '{"trajectory": ' + trajectory.to_json() + ', "rate": 25.0}'
    ).rate == pytest.approx(25.0)  # old requests' JSON stays valid
