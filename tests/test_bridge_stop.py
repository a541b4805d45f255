"""A bridge told to stop (SIGTERM) sends no new command, and answers; a
second bridge in the namespace does not start.

Real parts: a Zenoh router and ``python -m bridge.serve`` as processes
(``armplan.launch``), the simulated NAO as its own process over libqi, and a
Zenoh client session in the test; a slow link to the robot is a loopback
relay (:class:`~tests.slow_link.SlowLink`). Where a test needs the stop's
30 s limit shorter, the bridge service runs in the test's process
(:class:`BridgeService` on a real bus, the real sim), its stop given the
shorter limit.
"""

from __future__ import annotations

import contextlib
import logging
import re
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
from bridge.frames import DEFAULT_RATE
from bridge.minimum_jerk import minimum_jerk_trajectory
from bridge.naoqi_client import RETIRE_AFTER, NaoqiClient
from bridge.robot_bridge import RobotBridge
from bridge.service import BridgeService
from bridge.sim import SimProcess
from bridge.sim.log import read_log
from bridge.stopping import CUT_WAIT, STOP_GRACE, STOP_LIMIT
from shared.bus import Bus, ServiceHost, load_config
from shared.bus.robot_routes import BRIDGE, EXECUTE
from shared.errors import ArmplanError, ServiceUnavailableError
from shared.messages import ExecuteRequest, JointState, Trajectory
from shared.robot.postures import forward, rest
from tests.slow_link import SlowLink
from tests.test_bridge_watch import finished, last_moved, when_sim_logs


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

    def execute_in_background(
        self, trajectory: Trajectory, rate: float | None = None
    ) -> dict[str, Any]:
        """Send ``trajectory`` from a thread; the dict gets "reply" or "error"."""
        return execute_in_background(self.bus, trajectory, rate)

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


def execute_in_background(
    bus: Bus, trajectory: Trajectory, rate: float | None = None
) -> dict[str, Any]:
    """Send ``trajectory`` from a thread; the dict gets "reply" or "error"."""
    outcome: dict[str, Any] = {}

    def call() -> None:
        try:
            request = ExecuteRequest(trajectory=trajectory, rate=rate)
            outcome["reply"] = bus.call(EXECUTE, request, timeout=30.0)
        except ArmplanError as error:
            outcome["error"] = error

    outcome["thread"] = threading.Thread(target=call)
    outcome["thread"].start()
    return outcome


@contextlib.contextmanager
def running_stack(tmp_path: Path, bandwidth: float | None = None) -> Iterator[Stack]:
    """The stack; the bridge reaches the sim over a ``bandwidth`` [B/s] link
    if one is given."""
    config = load_config(endpoints=(free_endpoint(),))
    sim = SimProcess(log_path=tmp_path / "sim.jsonl")
    sim.start()
    link = None if bandwidth is None else link_to(sim, bandwidth)
    try:
        with (
            (tmp_path / "router.log").open("w") as router_log,
            (tmp_path / "bridge.log").open("w") as bridge_log,
            Launcher(config, [], log=router_log),
            RobotStack(
                config, robot=sim.url if link is None else link.url, log=bridge_log
            ) as robot,
            Bus.connect(config) as bus,
        ):
            yield Stack(robot, sim, bus)
    finally:
        if link is not None:
            link.close()
        sim.stop()


def link_to(sim: SimProcess, bandwidth: float) -> SlowLink:
    """A link of ``bandwidth`` [B/s] toward the sim."""
    return SlowLink(int(sim.url.rsplit(":", 1)[1]), bandwidth)


@pytest.fixture
def stack(tmp_path: Path) -> Iterator[Stack]:
    with running_stack(tmp_path) as running:
        yield running


class InProcess:
    """A router process, the sim, and the bridge service in this process."""

    def __init__(self, service: BridgeService, bus: Bus, sim: SimProcess) -> None:
        self.service = service
        self.bus = bus
        self.sim = sim


@contextlib.contextmanager
def in_process(
    tmp_path: Path, robot_url: str, sim: SimProcess, rate: float = DEFAULT_RATE
) -> Iterator[InProcess]:
    """A :class:`BridgeService` on a real bus, serving ``bridge/execute``
    (``rate``: the bridge's frame rate [Hz])."""
    config = load_config(endpoints=(free_endpoint(),))
    client = NaoqiClient(robot_url)
    try:
        with (
            (tmp_path / "router.log").open("w") as router_log,
            Launcher(config, [], log=router_log),
            Bus.connect(config) as served,
            Bus.connect(config) as bus,
        ):
            service = BridgeService(served, RobotBridge(client, rate=rate))
            with ServiceHost(served, BRIDGE, service.endpoints()):
                bus.wait_alive([BRIDGE], 10.0)
                yield InProcess(service, bus, sim)
    finally:
        client.close()


def from_forward(seconds: float) -> Trajectory:
    """Arm stretched forward -> rest: from rest, a 1.4 s approach first."""
    return minimum_jerk_trajectory(
        "right", [forward("right"), rest("right")], [seconds]
    )


def _assert_stopped_after_the_approach(stack: Stack, trajectory: Trajectory) -> None:
    """SIGTERM as ``trajectory``'s approach starts: the approach is played,
    the trajectory is not, the caller is told so and the bridge exits 0."""
    outcome = stack.execute_in_background(trajectory)
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


def test_a_bridge_stopped_during_the_approach_sends_no_trajectory(
    stack: Stack,
) -> None:
    """SIGTERM as the approach starts: the approach ends, the trajectory is
    not sent, and the caller is told so (it used to be sent after SIGTERM,
    then left unwatched, the caller told only that the bridge was gone)."""
    _assert_stopped_after_the_approach(stack, from_forward(2.0))


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
    _assert_stopped_after_the_approach(
        stack, minimum_jerk_trajectory("right", [far, far], [0.5])
    )
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
    assert BRIDGE_GRACE >= STOP_LIMIT + CUT_WAIT + RETIRE_AFTER + 2.0
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


def _terminated_after_sending(
    stack: Stack, rate: float, after: float
) -> dict[str, Any]:
    """A 4 s reach at ``rate`` [Hz]; SIGTERM to the bridge ``after`` [s] past its
    frames' publication; the caller's outcome once it has one (or 30 s)."""
    sent = threading.Event()
    frames = stack.bus.session.declare_subscriber(
        stack.bus.key("bridge/frames"), lambda _: sent.set()
    )
    trajectory = minimum_jerk_trajectory(
        "right", [rest("right"), forward("right")], [4.0]
    )
    outcome = stack.execute_in_background(trajectory, rate=rate)
    assert sent.wait(20.0)
    time.sleep(after)
    assert stack.robot.bridge is not None
    stack.robot.bridge.signal(signal.SIGTERM)
    outcome["thread"].join(30.0)
    frames.undeclare()
    return outcome


def test_a_trajectory_slow_to_reach_the_robot_is_watched_to_its_end(
    tmp_path: Path,
) -> None:
    """SIGTERM 0.5 s after a 4 s trajectory at 500 fps (260 kB) left over an
    80 kB/s link: the call reaches the robot over 3 s after it left, and
    plays to its end, 7 s after it left. The stop's wait was counted from
    when the call left (4 s + 2 s), so the bridge gave up a second before
    the end, the arm playing on unwatched ("for about 0.0 s more") and the
    caller answered by no one. Now it is counted from the call's arrival:
    the caller gets its report."""
    with running_stack(tmp_path, bandwidth=80e3) as stack:
        outcome = _terminated_after_sending(stack, rate=500.0, after=0.5)
        assert stack.bridge_exit() == 0
        played = finished(stack.sim)
    assert "error" not in outcome, outcome.get("error")
    report = outcome["reply"].report
    print(f"\nthe call began {report.start_delay:.2f} s after it left")
    assert report.start_delay > STOP_GRACE + 1.0  # the old bound: passed
    assert report.duration >= 4.0 - 2.0 * report.sample_period
    assert played == ["done"]
    assert "unwatched" not in (tmp_path / "bridge.log").read_text()


def test_a_bridge_exits_only_once_a_call_given_up_on_its_way_is_stopped(
    tmp_path: Path,
) -> None:
    """SIGTERM 0.3 s after a 4 s trajectory at 1000 fps (520 kB) left over an
    80 kB/s link: the call is given up (not arrived within its duration +
    1 s) and the stops follow it. The bridge used to exit at once, its
    stopper thread with it: the call reached the robot after the exit and
    played in full. Now the bridge exits once the call has ended, stopped
    as it took effect."""
    with running_stack(tmp_path, bandwidth=80e3) as stack:
        outcome = _terminated_after_sending(stack, rate=1000.0, after=0.3)
        code = stack.bridge_exit(BRIDGE_GRACE)
        exited = time.monotonic()
        began = when_sim_logs(stack.sim, "call", "angleInterpolation")
        time.sleep(max(0.0, began + 4.5 - time.monotonic()))  # its end, unstopped
        played, moved = finished(stack.sim), last_moved(stack.sim)
    print(
        f"\n{outcome.get('error')}\nthe call took effect {exited - began:.2f} s "
        "before the bridge exited"
    )
    assert code == 0
    assert isinstance(outcome.get("error"), ArmplanError)
    assert began < exited  # the bridge was still there when the call arrived
    assert played == []  # stopped, not played in full
    assert moved < began + 0.2


def test_a_stop_that_cannot_wait_for_the_end_stops_the_arm(
    tmp_path: Path, sim: SimProcess
) -> None:
    """A stop whose limit (1 s here; 30 s in the bridge process) passes 0.5 s
    into a 4 s trajectory stops the arm's motion tasks (as a robot given up
    is stopped) and answers the caller "the bridge is stopping; it stopped
    the arm at about t = ..."; it used to leave the arm playing unwatched
    and the caller told only that no queryable answered."""
    with in_process(tmp_path, sim.url, sim) as bridge:
        trajectory = minimum_jerk_trajectory(
            "right", [rest("right"), forward("right")], [4.0]
        )
        outcome = execute_in_background(bridge.bus, trajectory)
        began = when_sim_logs(sim, "motion", "angleInterpolation")
        time.sleep(max(0.0, began + 0.5 - time.monotonic()))
        assert bridge.service.stop(limit=1.0)
        outcome["thread"].join(10.0)
    error = outcome.get("error")
    assert isinstance(error, ServiceUnavailableError), outcome
    print(f"\n{error.reason}")
    found = re.fullmatch(
        r"the bridge is stopping; it stopped the arm at about t = (\d+\.\d) s of "
        r"4\.00 s \(its movement would end past the 1 s a stopping bridge waits "
        r"for it\): stopped it \(ALMotion\.killTasksUsingResources answered, the "
        r"call ended\)",
        error.reason,
    )
    assert found is not None, error.reason
    assert 1.3 <= float(found.group(1)) <= 1.5 + CUT_WAIT
    kill = when_sim_logs(sim, "call", "killTasksUsingResources")
    time.sleep(max(0.0, began + 4.2 - time.monotonic()))  # the unstopped end
    assert began + 1.3 < kill < began + 1.5 + CUT_WAIT
    assert last_moved(sim) < kill + 0.05
    assert finished(sim) == []


def test_a_stop_that_cuts_a_call_on_its_way_says_so(
    tmp_path: Path, sim: SimProcess
) -> None:
    """The stop's limit (1 s here) passes while a 4 s call at 1000 fps is
    still on its way over an 80 kB/s link: the caller was told "it stopped
    the arm at about t = 0.0 s". It is told the call had not reached the
    robot, and the stops follow it: it is ended as it takes effect."""
    link = link_to(sim, 80e3)
    try:
        with in_process(tmp_path, link.url, sim) as bridge:
            trajectory = minimum_jerk_trajectory(
                "right", [rest("right"), forward("right")], [4.0]
            )
            outcome = execute_in_background(bridge.bus, trajectory, rate=1000.0)
            time.sleep(1.0)  # the approach is none: the call is on its way
            assert bridge.service.stop(limit=0.5)
            outcome["thread"].join(10.0)
            assert bridge.service.robot.client.wait_stopped()
        began = when_sim_logs(sim, "call", "angleInterpolation")
        time.sleep(max(0.0, began + 4.5 - time.monotonic()))  # its end, unstopped
    finally:
        link.close()
    error = outcome.get("error")
    assert isinstance(error, ServiceUnavailableError), outcome
    print(f"\n{error.reason}")
    assert error.reason.startswith(
        "the bridge is stopping; the 4.00 s trajectory's call had not reached the "
        "robot yet (its movement would end past the 0.5 s a stopping bridge waits "
        "for it): "
    )
    assert "stopped the arm at about" not in error.reason
    assert finished(sim) == []
    assert last_moved(sim) < began + 0.2


def test_a_stop_that_gives_up_a_request_that_sent_nothing_says_so(
    tmp_path: Path, sim: SimProcess, caplog: pytest.LogCaptureFixture
) -> None:
    """A stop whose limit passes while the request being served is still
    connecting to the robot (its link silent): the log says nothing was sent
    for it. A stop could read the end time of the request before, and log
    that the robot played its trajectory on, unwatched, when nothing had
    been sent."""
    link = link_to(sim, 1e6)
    link.freeze()  # the connection is taken, nothing answers: 2 s to give up
    try:
        with in_process(tmp_path, link.url, sim) as bridge:
            request = from_forward(0.5)
            outcome = execute_in_background(bridge.bus, request)
            deadline = time.monotonic() + 10.0
            while link.connections == 0:  # the request holds the robot
                assert time.monotonic() < deadline
                time.sleep(0.005)
            with caplog.at_level(logging.WARNING, logger="armplan.bridge"):
                served = bridge.service.stop(limit=0.0)
            outcome["thread"].join(10.0)
    finally:
        link.close()
    assert not served
    text = caplog.text
    assert "leaving it: nothing was sent for it, and nothing will be" in text
    assert "unwatched" not in text
    assert "stopping the arm" not in text
    assert "error" in outcome
    assert not [e for e in read_log(sim.log_path) if e["event"] == "motion"]


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
    sim = SimProcess(log_path=tmp_path / "sim.jsonl")
    sim.start()
    trajectory = minimum_jerk_trajectory("right", [rest("right")] * 2, [1.0])
    try:
        with in_process(tmp_path, sim.url, sim, rate=50.0) as bridge:
            plain = ExecuteRequest(trajectory=trajectory)
            own = bridge.bus.call(EXECUTE, plain, timeout=30.0)
            asked = ExecuteRequest(trajectory=trajectory, rate=25.0)
            named = bridge.bus.call(EXECUTE, asked, timeout=30.0)
    finally:
        sim.stop()
    assert (own.frames, named.frames) == (50, 25)
    assert ExecuteRequest.model_validate_json(
        '{"trajectory": ' + trajectory.to_json() + ', "rate": 25.0}'
    ).rate == pytest.approx(25.0)  # old requests' JSON stays valid
