"""The bridge as a Zenoh service (``python -m bridge.serve``) driving the sim.

Real parts only: a Zenoh router and the bridge as processes
(``armplan.launch``), the simulated NAO as its own process reached through a
real libqi session on 127.0.0.1, and a Zenoh client session in the test. The
bridge is pointed at a fixed loopback address; each test starts its own sim
there, so the bridge also has to connect again to every new one.
"""

from __future__ import annotations

import os
import queue
import signal
import socket
import threading
import time
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import numpy as np
import pytest
import zenoh
from test_bridge import with_sample

from armplan.launch import Launcher, free_endpoint
from armplan.launch.robot import RobotStack
from bridge.address import check_robot_url, robot_url
from bridge.follower import offer_newest
from bridge.minimum_jerk import minimum_jerk_trajectory
from bridge.sim import SimProcess
from bridge.sim.log import read_log
from shared.bus import Bus, BusConfig, load_config
from shared.bus.robot_routes import EXECUTE
from shared.bus.routes import TRAJECTORY_TOPIC
from shared.errors import (
    ArmplanError,
    CallerDeadlineError,
    InvalidInputError,
    RobotBusyError,
    RobotUnavailableError,
    TrajectoryRefusedError,
)
from shared.messages import (
    CommandFrames,
    ExecuteReply,
    ExecuteRequest,
    JointState,
    TrackingReport,
    Trajectory,
)
from shared.robot.postures import forward, rest


def free_port() -> int:
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        return int(probe.getsockname()[1])


def reach(seconds: float = 1.0) -> Trajectory:
    """Rest -> arm stretched forward -> rest, minimum jerk, ``seconds`` each."""
    postures = [rest("right"), forward("right"), rest("right")]
    return minimum_jerk_trajectory("right", postures, [seconds, seconds])


def over_speed(trajectory: Trajectory) -> Trajectory:
    """``trajectory`` with sample 48 of RElbowYaw bumped by 0.4 rad: frame 12
    (t = 0.48 s) then needs about 10 rad/s, over the 8.27 rad/s limit. (The
    velocities are the bumped positions' own, as a trajectory that asks for
    the jump has: others would be refused as disagreeing with them.)"""
    return with_sample(trajectory, 48, 2, 0.4)


class Stack:
    """A router, a bridge aimed at ``url``, and a client bus."""

    def __init__(self, config: BusConfig, url: str, bus: Bus, log: Path) -> None:
        self.config = config
        self.url = url
        self.bus = bus
        self.log = log  # the bridge's log file

    def execute(self, trajectory: Trajectory, timeout: float = 30.0) -> ExecuteReply:
        return self.bus.call(
            EXECUTE, ExecuteRequest(trajectory=trajectory), timeout=timeout
        )


@pytest.fixture(scope="module")
def stack(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Stack]:
    config = load_config(endpoints=(free_endpoint(),))
    url = f"tcp://127.0.0.1:{free_port()}"
    logs = tmp_path_factory.mktemp("logs")
    with (
        (logs / "router.log").open("w") as router_log,
        (logs / "bridge.log").open("w") as bridge_log,
        Launcher(config, [], log=router_log),
        RobotStack(config, robot=url, follow=True, log=bridge_log),
        Bus.connect(config) as bus,
    ):
        yield Stack(config, url, bus, logs / "bridge.log")


@pytest.fixture
def sim(stack: Stack, tmp_path: Path) -> Iterator[SimProcess]:
    process = SimProcess(listen=stack.url, log_path=tmp_path / "sim.jsonl")
    process.start()
    try:
        yield process
    finally:
        process.stop()


class Published:
    """Every message put on ``<ns>/bridge/**`` while it is open, by key."""

    def __init__(self, bus: Bus) -> None:
        self.keys: list[str] = []
        self.payloads: list[bytes] = []
        self._lock = threading.Lock()
        self._subscriber = bus.session.declare_subscriber(
            bus.key("bridge/**"), self._on
        )

    def _on(self, sample: zenoh.Sample) -> None:
        with self._lock:
            self.keys.append(str(sample.key_expr))
            self.payloads.append(sample.payload.to_bytes())

    def on(self, key: str) -> list[bytes]:
        with self._lock:
            return [
                p for k, p in zip(self.keys, self.payloads, strict=True) if k == key
            ]

    def close(self) -> None:
        self._subscriber.undeclare()


@pytest.fixture
def published(stack: Stack) -> Iterator[Published]:
    listener = Published(stack.bus)
    try:
        yield listener
    finally:
        listener.close()


def commands_received(sim: SimProcess) -> list[dict[str, Any]]:
    """The sim's log entries for commands it got (calls and motions)."""
    assert sim.log_path is not None
    return [e for e in read_log(sim.log_path) if e["event"] in ("call", "motion")]


def test_a_full_follower_queue_drops_its_oldest_not_the_newest() -> None:
    """Three slots, five trajectories offered: the last three wait, in order;
    the two oldest went, each offer saying whether it dropped one."""
    waiting: queue.Queue[bytes | None] = queue.Queue(3)
    dropped = [offer_newest(waiting, bytes([i])) for i in range(5)]
    assert dropped == [False, False, False, True, True]
    assert [waiting.get_nowait() for _ in range(3)] == [b"\x02", b"\x03", b"\x04"]


def test_robot_addresses_are_checked() -> None:
    """--robot, then $ARMPLAN_ROBOT, then the sim's address; a malformed one is
    refused with a message that shows the expected form."""
    assert robot_url(None, {}) == "tcp://127.0.0.1:9559"
    assert robot_url(None, {"ARMPLAN_ROBOT": "tcp://10.0.0.7:9559"}) == (
        "tcp://10.0.0.7:9559"
    )
    assert robot_url("tcp://nao.local:9559", {"ARMPLAN_ROBOT": "x"}) == (
        "tcp://nao.local:9559"
    )
    for bad in ("10.0.0.7:9559", "tcp://10.0.0.7", "tcp://h:70000", "udp://h:1"):
        with pytest.raises(InvalidInputError) as caught:
            check_robot_url(bad)
        assert caught.value.message == (
            f"robot address {bad!r} must look like tcp://HOST:PORT "
            "(a real NAO: tcp://IP:9559)"
        )


def test_an_over_speed_trajectory_is_refused_and_the_sim_receives_nothing(
    stack: Stack, sim: SimProcess, published: Published
) -> None:
    """One frame over RElbowYaw's speed limit: the caller gets the typed
    refusal naming joint, frame and limit; the sim's log shows no command and
    the bridge publishes no frames."""
    with pytest.raises(TrajectoryRefusedError) as caught:
        stack.execute(over_speed(reach()))
    error = caught.value
    print("\n" + error.message)
    assert error.message.startswith("trajectory refused, nothing was sent: RElbowYaw")
    assert error.evidence["joint"] == "RElbowYaw"
    assert error.evidence["frame"] == 12
    assert error.evidence["time"] == pytest.approx(0.48)
    assert error.evidence["value"] > error.evidence["limit"]
    time.sleep(0.3)  # anything sent would have been logged by now
    assert commands_received(sim) == []
    assert published.on(stack.bus.key("bridge/frames")) == []


def test_a_trajectory_away_from_the_arm_with_the_approach_off_sends_nothing(
    stack: Stack, sim: SimProcess, published: Published
) -> None:
    """The arm rests; a trajectory starting at the arm stretched forward, with
    the approach off, is refused naming the start: no command (not even
    stiffness) reaches the sim and no frames are published as if played."""
    trajectory = minimum_jerk_trajectory(
        "right", [forward("right"), rest("right")], [1.0]
    )
    with pytest.raises(TrajectoryRefusedError) as caught:
        stack.bus.call(
            EXECUTE, ExecuteRequest(trajectory=trajectory, approach=False), timeout=30
        )
    assert "the approach move is off" in caught.value.message
    time.sleep(0.3)  # anything sent would have been logged by now
    assert commands_received(sim) == []
    assert published.on(stack.bus.key("bridge/frames")) == []


def test_a_trajectory_is_played_reported_and_published(
    stack: Stack, sim: SimProcess, published: Published
) -> None:
    """A reach through Zenoh: tracking under 1 degree RMS per joint; the frames,
    every measured state and the report are published as typed messages."""
    trajectory = reach()
    reply = stack.execute(trajectory)
    report = reply.report
    print(
        "\ntracking RMS [deg]:",
        {k: round(v, 3) for k, v in report.tracking_rms_deg.items()},
    )
    assert set(report.tracking_rms_deg) == set(trajectory.joint_names)
    assert max(report.tracking_rms_deg.values()) < 1.0
    # The whole trajectory was sampled; how long after its end the last
    # reading came depends on the host's load (CI compiles beside it).
    assert report.duration >= trajectory.duration - 2.0 * report.sample_period
    assert report.duration <= trajectory.duration + 0.5
    time.sleep(0.3)  # let the last publications arrive
    frames = published.on(stack.bus.key("bridge/frames"))
    states = published.on(stack.bus.key("bridge/state"))
    reports = published.on(stack.bus.key("bridge/report"))
    assert len(frames) == 1 and len(reports) == 1
    assert len(CommandFrames.model_validate_json(frames[0]).times) == reply.frames
    assert TrackingReport.model_validate_json(reports[0]) == report
    assert len(states) >= report.samples
    last = JointState.model_validate_json(states[-1])
    assert last.joint_names == trajectory.joint_names
    assert not [e for e in read_log(sim.log_path or "") if e["event"] == "refused"]


def test_the_approach_states_are_published_before_the_trajectorys(
    stack: Stack, sim: SimProcess, published: Published
) -> None:
    """A trajectory starting with the arm stretched forward, the arm at rest:
    the approach's measured states were not published, so a recording missed
    the arm's first movement. They now come first, their times negative
    (counted to the trajectory's start) and over the approach's length, the
    first at the rest posture, the last at the trajectory's start."""
    trajectory = minimum_jerk_trajectory(
        "right", [forward("right"), rest("right")], [1.0]
    )
    reply = stack.execute(trajectory)
    assert reply.approach_duration >= 0.5
    time.sleep(0.3)  # let the last publications arrive
    states = [
        JointState.model_validate_json(m)
        for m in published.on(stack.bus.key("bridge/state"))
    ]
    before = [s for s in states if s.time < 0.0]
    assert len(before) >= 0.5 * reply.approach_duration / 0.05
    assert states[: len(before)] == before  # all of them first, in order
    assert before[0].time >= -reply.approach_duration - 0.1
    np.testing.assert_allclose(before[0].positions, rest("right"), atol=0.05)
    np.testing.assert_allclose(before[-1].positions, forward("right"), atol=0.05)
    assert len(states) - len(before) >= reply.report.samples


def test_the_bridge_log_announces_the_approach_before_the_frames(
    stack: Stack, sim: SimProcess
) -> None:
    """An operator reading the bridge's log learns the arm is about to move
    to the trajectory's start, and for how long, before the frames play;
    with the arm already there, no approach is announced."""
    away = minimum_jerk_trajectory("right", [forward("right"), rest("right")], [1.0])
    there = minimum_jerk_trajectory("right", [rest("right"), forward("right")], [1.0])
    before = stack.log.read_text().splitlines()
    moved = stack.execute(away)
    stayed = stack.execute(there)
    lines = stack.log.read_text().splitlines()[len(before) :]
    told = [k for k, line in enumerate(lines) if "approaching" in line]
    played = [k for k, line in enumerate(lines) if "playing" in line]
    assert len(told) == 1 and len(played) == 2, lines
    assert played[0] > told[0] and stayed.approach_duration == 0.0
    assert (
        f"({moved.approach_duration:.2f} s, right arm) on {stack.url}"
        in (lines[told[0]])
    )


def test_a_published_trajectory_is_followed(
    stack: Stack, sim: SimProcess, published: Published
) -> None:
    """With --follow, a trajectory put on plan/trajectory is played: the sim
    moves and a tracking report is published."""
    stack.bus.publish(TRAJECTORY_TOPIC, reach(0.6))
    deadline = time.monotonic() + 20.0
    while not published.on(stack.bus.key("bridge/report")):
        assert time.monotonic() < deadline, "no report within 20 s"
        time.sleep(0.1)
    report = TrackingReport.model_validate_json(
        published.on(stack.bus.key("bridge/report"))[0]
    )
    assert max(report.tracking_rms_deg.values()) < 1.0
    assert [e for e in commands_received(sim) if e["event"] == "motion"]


def test_a_request_while_the_robot_plays_is_refused_not_queued(
    stack: Stack, sim: SimProcess
) -> None:
    """A second execute during a 2 s trajectory: robot_busy at once, naming the
    time left; the first plays to its end, and the sim received one movement.
    (Queued, 95 of 100 flooded requests whose callers had timed out were
    played one after another for minutes.)"""
    outcome: dict[str, Any] = {}

    def first() -> None:
        outcome["reply"] = stack.execute(reach())

    caller = threading.Thread(target=first)
    caller.start()
    try:
        time.sleep(0.5)
        with pytest.raises(RobotBusyError) as caught:
            stack.execute(reach(), timeout=5.0)
    finally:
        caller.join(30.0)
    assert caught.value.message.startswith(
        f"the robot at {stack.url} is playing another trajectory (about "
    )
    assert 0.0 < caught.value.evidence["remaining"] <= 2.0
    assert max(outcome["reply"].report.tracking_rms_deg.values()) < 1.0
    motions = [e for e in commands_received(sim) if e["event"] == "motion"]
    assert [m["method"] for m in motions].count("angleInterpolation") == 1


def test_the_time_left_told_a_refused_caller_counts_from_after_the_approach(
    stack: Stack, sim: SimProcess, published: Published
) -> None:
    """A 2 s trajectory from the arm stretched forward, the arm at rest: a
    caller refused just as its frames go out was told the time left from the
    lock, less the approach (about 1 s too little); now from the frames."""
    outcome: dict[str, Any] = {}
    trajectory = minimum_jerk_trajectory(
        "right", [forward("right"), rest("right")], [2.0]
    )

    def first() -> None:
        outcome["reply"] = stack.execute(trajectory)

    caller = threading.Thread(target=first)
    caller.start()
    try:
        deadline = time.monotonic() + 20.0
        while not published.on(stack.bus.key("bridge/frames")):
            assert time.monotonic() < deadline, "no frames within 20 s"
            time.sleep(0.01)
        with pytest.raises(RobotBusyError) as caught:
            stack.execute(reach(), timeout=5.0)
    finally:
        caller.join(30.0)
    assert outcome["reply"].approach_duration >= 0.9
    assert caught.value.evidence["remaining"] >= trajectory.duration - 0.45


def test_while_the_robot_plays_a_trajectory_over_a_limit_is_refused_as_such(
    stack: Stack, sim: SimProcess
) -> None:
    """An over-speed trajectory sent while another plays was refused with
    robot_busy (the lock came before the check), so its caller would send
    it again later, only to learn then that it can never play. Now it is
    trajectory_refused, naming the frame, busy or not."""
    outcome: dict[str, Any] = {}

    def first() -> None:
        outcome["reply"] = stack.execute(reach())

    caller = threading.Thread(target=first)
    caller.start()
    try:
        time.sleep(0.5)
        with pytest.raises(TrajectoryRefusedError) as caught:
            stack.execute(over_speed(reach()), timeout=5.0)
    finally:
        caller.join(30.0)
    assert caught.value.evidence["joint"] == "RElbowYaw"
    assert max(outcome["reply"].report.tracking_rms_deg.values()) < 1.0


def test_the_time_left_told_a_caller_refused_during_the_approach_counts_it(
    stack: Stack, sim: SimProcess
) -> None:
    """A 2 s trajectory from the arm stretched forward, the arm at rest: a
    caller refused during the 1.4 s approach was told about 2 s left, the
    trajectory alone; now the approach's rest too."""
    trajectory = minimum_jerk_trajectory(
        "right", [forward("right"), rest("right")], [2.0]
    )
    states: queue.Queue[JointState] = queue.Queue()
    subscriber = stack.bus.session.declare_subscriber(
        stack.bus.key("bridge/state"),
        lambda s: states.put(JointState.model_validate_json(s.payload.to_bytes())),
    )
    outcome: dict[str, Any] = {}

    def first() -> None:
        outcome["reply"] = stack.execute(trajectory)

    caller = threading.Thread(target=first)
    caller.start()
    try:
        while states.get(timeout=20.0).time >= -1.0:  # over 1 s of approach left
            pass
        with pytest.raises(RobotBusyError) as caught:
            stack.execute(reach(), timeout=5.0)
    finally:
        caller.join(30.0)
        subscriber.undeclare()  # type: ignore[no-untyped-call]
    assert outcome["reply"].approach_duration >= 1.0
    assert caught.value.evidence["remaining"] >= trajectory.duration + 0.5


def test_a_caller_who_cannot_wait_for_the_trajectory_is_refused_at_once(
    stack: Stack, sim: SimProcess, published: Published
) -> None:
    """A 2 s trajectory, a caller who waits 1 s: caller_deadline at once,
    naming both times; the robot receives nothing. (The arm used to play it
    all for no one, the caller told request_timeout.)"""
    started = time.monotonic()
    with pytest.raises(CallerDeadlineError) as caught:
        stack.execute(reach(), timeout=1.0)
    assert time.monotonic() - started < 1.0
    error = caught.value
    assert "the 2.00 s trajectory alone" in error.message
    assert error.message.startswith(f"the robot at {stack.url}: the caller stops ")
    assert error.evidence["duration"] == pytest.approx(2.0)
    assert 0.0 < error.evidence["left"] < 1.0
    assert error.evidence["outcome"] == "nothing was sent"
    time.sleep(0.3)  # anything sent would have been logged by now
    assert commands_received(sim) == []
    assert published.on(stack.bus.key("bridge/frames")) == []


def test_a_caller_who_cannot_wait_for_the_approach_too_is_refused_before_it(
    stack: Stack, sim: SimProcess
) -> None:
    """A 1 s trajectory from the arm stretched forward, the arm at rest, a
    caller who waits 1.5 s: the trajectory alone fits, with the approach it
    does not; refused naming both, before the approach (no movement sent)."""
    trajectory = minimum_jerk_trajectory(
        "right", [forward("right"), rest("right")], [1.0]
    )
    with pytest.raises(CallerDeadlineError) as caught:
        stack.execute(trajectory, timeout=1.5)
    error = caught.value
    assert error.evidence["approach"] >= 0.9
    assert f"{error.evidence['approach']:.2f} s approach + 1.00 s trajectory" in (
        error.message
    )
    assert error.evidence["outcome"] == "nothing was sent"
    motions = [e for e in commands_received(sim) if e["event"] == "motion"]
    assert motions == []


def test_a_caller_gone_during_a_slow_approach_gets_no_trajectory(
    stack: Stack, sim: SimProcess, published: Published
) -> None:
    """The caller's time covers approach and trajectory with 0.4 s to spare,
    but the robot stalls 0.6 s (SIGSTOP) as the approach ends, and answers
    its call that much later: the caller would be gone before the trajectory
    ended, so its frames are neither sent nor published; caller_deadline
    says the arm is at the start. (They used to be sent for no one.)"""
    trajectory = minimum_jerk_trajectory(
        "right", [forward("right"), rest("right")], [1.0]
    )
    approach = stack.execute(trajectory).approach_duration  # ends at rest again
    assert approach >= 0.9
    time.sleep(0.3)  # the first one's last states arrive
    seen = len(published.on(stack.bus.key("bridge/state")))
    outcome: dict[str, Any] = {}

    def call() -> None:
        try:
            outcome["reply"] = stack.execute(trajectory, timeout=approach + 1.45)
        except ArmplanError as error:
            outcome["error"] = error

    def approach_ends_soon() -> bool:
        """A state of the approach within 0.2 s of its end has come."""
        states = published.on(stack.bus.key("bridge/state"))[seen:]
        return any(JointState.model_validate_json(m).time > -0.2 for m in states)

    caller = threading.Thread(target=call)
    caller.start()
    try:
        deadline = time.monotonic() + 10.0
        while not approach_ends_soon():
            assert time.monotonic() < deadline, "no approach within 10 s"
            time.sleep(0.005)
        os.kill(sim.pid, signal.SIGSTOP)
        time.sleep(0.6)  # under the bridge's 1 s without a reading
    finally:
        os.kill(sim.pid, signal.SIGCONT)
        caller.join(10.0)
    error = outcome["error"]
    assert isinstance(error, CallerDeadlineError), error
    assert error.evidence["outcome"] == (
        "the arm is at the trajectory's start; nothing of the trajectory was sent"
    )
    assert error.evidence["left"] < 1.0
    assert "the 1.00 s trajectory" in error.message
    calls = [e for e in commands_received(sim) if e["event"] == "motion"]
    assert [c["method"] for c in calls].count("angleInterpolation") == 3
    assert len(published.on(stack.bus.key("bridge/frames"))) == 1  # the first's


def test_a_sim_killed_mid_trajectory_errs_within_2_s_and_is_used_again(
    stack: Stack, tmp_path: Path
) -> None:
    """SIGKILL the sim 0.5 s into a 2 s trajectory: the Zenoh caller gets
    robot_unavailable within 2 s; a sim restarted at the same address is used
    by the same bridge process for the next request."""
    first = SimProcess(listen=stack.url, log_path=tmp_path / "first.jsonl")
    second = SimProcess(listen=stack.url, log_path=tmp_path / "second.jsonl")
    outcome: dict[str, Any] = {}

    def call() -> None:
        try:
            stack.execute(reach())
        except RobotUnavailableError as error:
            outcome["error"], outcome["at"] = error, time.monotonic()

    first.start()
    try:
        caller = threading.Thread(target=call)
        caller.start()
        time.sleep(0.5)
        killed_at = time.monotonic()
        first.kill()
        caller.join(10.0)
        error = outcome["error"]
        delay = outcome["at"] - killed_at
        print(f"\nerror {delay * 1000:.0f} ms after the kill: {error.message}")
        assert error.evidence["url"] == stack.url
        assert error.message.startswith(f"the robot at {stack.url} is unavailable")
        assert 0.0 < delay < 2.0
        with pytest.raises(RobotUnavailableError):  # nobody there now
            stack.execute(reach())
        second.start()
        again = stack.execute(reach())
        assert max(again.report.tracking_rms_deg.values()) < 1.0
    finally:
        first.stop()
        second.stop()


def test_a_reading_after_the_bus_closed_is_dropped_not_raised() -> None:
    """A stop that gave up on a long trajectory closes the bus while its
    readings go on: each raised 'session closed' in the play's thread (an
    untyped traceback in the bridge's log); now it is dropped."""
    from bridge.robot_bridge import RobotBridge
    from bridge.service import BridgeService
    from shared.bus import open_router

    config = BusConfig(endpoints=(free_endpoint(),))
    state = JointState(time=0.5, joint_names=["RShoulderPitch"], positions=[0.1])
    with open_router(config):
        bus = Bus.connect(config)
        service = BridgeService(bus, RobotBridge(client=None))  # type: ignore[arg-type]
        service._publish_state(state)  # the bus is open: published
        bus.close()
        service._publish_state(state)  # closed: dropped
