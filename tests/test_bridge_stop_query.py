"""``<ns>/bridge/stop``: any Zenoh client stops the arm the bridge moves.

Real parts: a Zenoh router process (``armplan.launch``), the simulated NAO
as its own process over libqi, a :class:`BridgeService` (and, for
``--follow``, its follower) in this process on a real Zenoh session, a
client session asking ``bridge/execute`` from a thread and ``bridge/stop``;
a libqi session of the test's own reads the sim's measured angles. The
bridge serves with ONE worker: a stop queued behind the blocking execute
would be answered only once the trajectory had played.
"""

from __future__ import annotations

import contextlib
import logging
import os
import signal
import subprocess
import sys
import threading
import time
from collections.abc import Iterator
from dataclasses import replace
from pathlib import Path
from typing import Any

import numpy as np
import pytest
import zenoh

from armplan.launch import Launcher, free_endpoint
from bridge.follower import TrajectoryFollower
from bridge.minimum_jerk import minimum_jerk_trajectory
from bridge.naoqi_client import NaoqiClient
from bridge.robot_bridge import RobotBridge
from bridge.service import BridgeService
from bridge.sim import SimProcess
from bridge.sim.log import read_log
from shared.bus import Bus, ServiceHost, load_config
from shared.bus.deadline import budget_attachment
from shared.bus.robot_routes import BRIDGE, EXECUTE, STOP
from shared.bus.routes import TRAJECTORY_TOPIC
from shared.bus.topics import BRIDGE_OUTCOME_TOPIC, BRIDGE_STATE_TOPIC
from shared.errors import (
    ArmplanError,
    RequestTimeoutError,
    ServiceUnavailableError,
)
from shared.libqi import qi
from shared.messages import (
    ExecuteRequest,
    ExecutionOutcome,
    JointState,
    StopReply,
    StopRequest,
    Trajectory,
)
from shared.robot import Side
from shared.robot.postures import forward, rest

REPO = Path(__file__).resolve().parents[1]
NAMES = list(Side.RIGHT.joint_names)
#: The long trajectory: rest -> arm stretched forward, no approach needed
#: (the sim starts at rest).
LONG = 4.0


def _reach(seconds: float) -> Trajectory:
    return minimum_jerk_trajectory(
        "right", [rest("right"), forward("right")], [seconds]
    )


def _wait(what: str, done: Any, within: float = 15.0) -> None:
    deadline = time.monotonic() + within
    while not done():
        assert time.monotonic() < deadline, f"{what}: not within {within:g} s"
        time.sleep(0.01)


class Served:
    """The router, the sim, the bridge service (one worker) and a client bus."""

    def __init__(
        self,
        bus: Bus,
        service: BridgeService,
        sim: SimProcess,
        follower: TrajectoryFollower | None,
    ) -> None:
        self.bus, self.service, self.sim, self.follower = bus, service, sim, follower
        self.states: list[JointState] = []
        self.outcomes: list[ExecutionOutcome] = []
        self._subscribers = [
            bus.session.declare_subscriber(bus.key(BRIDGE_STATE_TOPIC), self._state),
            bus.session.declare_subscriber(
                bus.key(BRIDGE_OUTCOME_TOPIC), self._outcome
            ),
        ]
        self._qi = qi.Session()
        self._qi.connect(sim.url)
        self._motion = self._qi.service("ALMotion")

    def _state(self, sample: zenoh.Sample) -> None:
        self.states.append(JointState.model_validate_json(sample.payload.to_bytes()))

    def _outcome(self, sample: zenoh.Sample) -> None:
        self.outcomes.append(
            ExecutionOutcome.model_validate_json(sample.payload.to_bytes())
        )

    def measured(self) -> np.ndarray:
        """The right arm's measured angles now [rad], read by the test."""
        return np.array(self._motion.getAngles(NAMES, True), dtype=float)

    def sim_calls(self, method: str) -> int:
        assert self.sim.log_path is not None
        return sum(
            1
            for e in read_log(self.sim.log_path)
            if e["event"] == "call" and e.get("method") == method
        )

    def execute_in_background(
        self, trajectory: Trajectory, rate: float | None = None
    ) -> dict[str, Any]:
        """Ask ``bridge/execute`` from a thread; the dict gets "reply" or "error"."""
        outcome: dict[str, Any] = {}

        def call() -> None:
            try:
                request = ExecuteRequest(trajectory=trajectory)
                if rate is not None:
                    request = ExecuteRequest(trajectory=trajectory, rate=rate)
                outcome["reply"] = self.bus.call(EXECUTE, request, timeout=30.0)
            except ArmplanError as error:
                outcome["error"] = error

        outcome["thread"] = threading.Thread(target=call)
        outcome["thread"].start()
        return outcome

    def wait_for_state(self, after: float) -> None:
        _wait(
            f"a state after t = {after} s",
            lambda: any(s.time > after for s in list(self.states)),
        )

    def close(self) -> None:
        for subscriber in self._subscribers:
            subscriber.undeclare()  # type: ignore[no-untyped-call]
        self._qi.close()


@contextlib.contextmanager
def served(
    tmp_path: Path,
    sim: SimProcess,
    follow: bool = False,
    queue_limit: int = 0,
    max_payload: int = 0,
    url: str | None = None,
) -> Iterator[Served]:
    config = load_config(endpoints=(free_endpoint(),))
    client = NaoqiClient(url or sim.url)
    try:
        with (
            (tmp_path / "router.log").open("w") as router_log,
            Launcher(config, [], log=router_log),
            Bus.connect(
                replace(
                    config,
                    workers=1,
                    queue_limit=queue_limit or config.queue_limit,
                    max_payload=max_payload or config.max_payload,
                )
            ) as bridge_bus,
            Bus.connect(config) as bus,
        ):
            service = BridgeService(bridge_bus, RobotBridge(client))
            follower = TrajectoryFollower(service) if follow else None
            with ServiceHost(bridge_bus, BRIDGE, service.endpoints()):
                if follower is not None:
                    follower.start()
                bus.wait_alive([BRIDGE], 10.0)
                there = Served(bus, service, sim, follower)
                try:
                    yield there
                finally:
                    there.close()
                    if follower is not None:
                        follower.stop()
    finally:
        client.close()


def _assert_stopped_mid_way(there: Served) -> np.ndarray:
    """The sim's arm holds still, well short of the trajectory's end."""
    before = there.measured()
    time.sleep(0.3)
    after = there.measured()
    print(f"\nheld after the stop [rad]: {after.round(4).tolist()}")
    assert np.abs(after - before).max() < 1e-3  # still
    assert np.abs(after - np.array(forward("right"))).max() > 0.2  # not at the end
    assert np.abs(after - np.array(rest("right"))).max() > 0.05  # it had moved
    return after


def test_a_stop_query_stops_the_trajectory_playing_at_once(
    tmp_path: Path, sim: SimProcess
) -> None:
    """1 s into a 4 s trajectory, ``bridge/stop`` (while the execute query
    blocks the bridge's only worker): the arm is stopped where it is, the
    execute caller gets the robot's stopped error, the outcome says who
    stopped it, and the reply comes once the arm is still. An execute
    query after it plays as usual (a stop is no latch)."""
    with served(tmp_path, sim) as there:
        running = there.execute_in_background(_reach(LONG))
        there.wait_for_state(1.0)
        asked = time.monotonic()
        reply = there.bus.call(STOP, StopRequest(reason="test e-stop"), timeout=10.0)
        took = time.monotonic() - asked
        print(f"\n{reply.to_json()} in {took:.2f} s")
        running["thread"].join(10.0)
        assert not running["thread"].is_alive()
        assert isinstance(reply, StopReply)
        assert (reply.playing, reply.stopped, reply.arm, reply.phase) == (
            True,
            True,
            "right",
            "trajectory",
        )
        assert reply.played is not None and 0.9 < reply.played < 2.5
        assert reply.phase_duration == pytest.approx(LONG, abs=0.05)
        assert reply.still and reply.dropped == 0
        assert reply.reason == "test e-stop"
        assert took < 2.5  # not after the trajectory's end (3 s later)
        error = running.get("error")
        assert isinstance(error, ArmplanError), running
        assert error.kind == "robot_state" and error.evidence.get("stopped")
        assert error.evidence["stopped_by"] == "bridge/stop"
        assert "a bridge/stop query stopped the movement at t = " in error.message
        assert 'reason: "test e-stop"' in error.message
        assert there.sim_calls("killTasksUsingResources") >= 1
        _assert_stopped_mid_way(there)
        _wait("the outcome", lambda: len(there.outcomes) == 1)
        (outcome,) = there.outcomes
        assert (outcome.outcome, outcome.phase, outcome.stopped_by) == (
            "stopped",
            "trajectory",
            "bridge/stop",
        )
        assert outcome.stop_reason == "test e-stop"
        assert outcome.played == reply.played
        # not a latch: the next execute query plays (an approach, then 1 s)
        again = there.bus.call(
            EXECUTE, ExecuteRequest(trajectory=_reach(1.0)), timeout=20.0
        )
        assert again.approach_duration > 0.0
        assert np.abs(there.measured() - np.array(forward("right"))).max() < 0.02


def test_a_stop_query_in_the_approach_sends_nothing_of_the_trajectory(
    tmp_path: Path, sim: SimProcess
) -> None:
    """Stopped 0.3 s into the approach to a trajectory's start: the approach
    is stopped where it is, and the trajectory is never sent."""
    from_forward = minimum_jerk_trajectory(
        "right", [forward("right"), rest("right")], [2.0]
    )
    with served(tmp_path, sim) as there:
        running = there.execute_in_background(from_forward)
        there.wait_for_state(-10.0)  # the approach's first state
        time.sleep(0.3)
        reply = there.bus.call(STOP, StopRequest(), timeout=10.0)
        print(f"\n{reply.to_json()}")
        running["thread"].join(10.0)
        assert (reply.playing, reply.stopped, reply.phase) == (True, True, "approach")
        assert reply.played is not None and reply.phase_duration is not None
        assert 0.1 < reply.played < reply.phase_duration
        error = running["error"]
        assert "a bridge/stop query stopped the approach at t = " in error.message
        assert "nothing of the trajectory was sent" in error.message
        time.sleep(0.5)
        assert there.sim_calls("angleInterpolation") == 1  # the approach alone
        _assert_stopped_mid_way(there)
        _wait("the outcome", lambda: len(there.outcomes) == 1)
        assert there.outcomes[0].phase == "approach"


def test_a_stop_with_nothing_playing_answers_at_once(
    tmp_path: Path, sim: SimProcess
) -> None:
    """Nothing playing: answered at once, playing false, still from a reading
    of both arms settled; twice the same."""
    with served(tmp_path, sim) as there:
        for _ in range(2):
            asked = time.monotonic()
            reply = there.bus.call(STOP, "{}", timeout=5.0)
            assert time.monotonic() - asked < 1.0
            assert (reply.playing, reply.stopped, reply.still) == (False, False, True)
            assert reply.arm is None and reply.dropped == 0 and reply.waited < 0.5
            assert reply.ended is None and reply.note is None
            assert reply.reason is None
        assert there.sim_calls("killTasksUsingResources") == 0
        assert there.outcomes == []


@pytest.mark.parametrize(
    "payload",
    [
        "not json",
        '{"reason": "a\\u0000b\\nFAKE LOG LINE", "source": "lab gui"}',
    ],
    ids=["not-json", "extra-field-control-characters"],
)
def test_any_payload_on_bridge_stop_stops_the_arm(
    tmp_path: Path, sim: SimProcess, payload: str, caplog: pytest.LogCaptureFixture
) -> None:
    """A payload that is no JSON, or one with a field the bridge does not
    know and a reason with a NUL and a line break: the arm is stopped all
    the same, the reply notes what was ignored, and no log line carries a
    control character (no forged log line)."""
    caplog.set_level(logging.INFO, logger="armplan")
    with served(tmp_path, sim) as there:
        running = there.execute_in_background(_reach(LONG))
        there.wait_for_state(1.0)
        reply = there.bus.call(STOP, payload, timeout=10.0)
        print(f"\n{reply.to_json()}")
        running["thread"].join(10.0)
        assert (reply.playing, reply.stopped, reply.ended) == (True, True, True)
        assert reply.still and reply.note
        error = running["error"]
        assert error.evidence["stopped_by"] == "bridge/stop"
        if payload == "not json":
            assert "not JSON" in reply.note and reply.reason is None
        else:
            assert "'source'" in reply.note and "control characters" in reply.note
            assert reply.reason == "ab FAKE LOG LINE"
            assert error.evidence["stop_reason"] == "ab FAKE LOG LINE"
        _assert_stopped_mid_way(there)
    lines = [r.getMessage() for r in caplog.records]
    assert any("stop: asked on" in line for line in lines)
    for line in lines:
        assert not any(ord(c) < 32 for c in line), repr(line)


@pytest.mark.parametrize("hurry", ["clock-behind", "1-ms-timeout"])
def test_a_stop_is_made_whatever_its_callers_deadline(
    tmp_path: Path, sim: SimProcess, hurry: str
) -> None:
    """A stop sent "15 s ago" (10 s to wait) by a caller's clock that is
    behind, or one whose caller waits 1 ms: the arm is stopped all the
    same; the first is answered in full (its caller does wait)."""
    with served(tmp_path, sim) as there:
        running = there.execute_in_background(_reach(LONG))
        there.wait_for_state(1.0)
        if hurry == "clock-behind":
            replies = list(
                there.bus.session.get(
                    there.bus.key(STOP.path),
                    payload=b'{"reason": "hurried"}',
                    attachment=budget_attachment(10.0, sent=time.time() - 15.0),
                    timeout=10.0,
                )
            )
            assert len(replies) == 1 and replies[0].ok is not None
            reply = StopReply.model_validate_json(replies[0].ok.payload.to_bytes())
            print(f"\n{reply.to_json()}")
            assert (reply.playing, reply.stopped, reply.ended, reply.still) == (
                True,
                True,
                True,
                True,
            )
        else:
            with pytest.raises(RequestTimeoutError):
                there.bus.call(STOP, StopRequest(reason="hurried"), timeout=0.001)
        running["thread"].join(10.0)
        assert running["error"].evidence["stop_reason"] == "hurried"
        _wait("the outcome", lambda: len(there.outcomes) == 1)
        assert there.outcomes[0].outcome == "stopped"
        _assert_stopped_mid_way(there)


def test_a_stop_query_drops_every_trajectory_the_follower_holds(
    tmp_path: Path, sim: SimProcess
) -> None:
    """``--follow`` with three trajectories published: a stop during the
    first stops it and drops the two waiting (counted in the reply); one
    published after the stop plays."""
    with served(tmp_path, sim, follow=True) as there:
        follower = there.follower
        assert follower is not None
        for seconds in (LONG, 1.0, 1.0):
            there.bus.publish(TRAJECTORY_TOPIC, _reach(seconds))
        there.wait_for_state(0.8)
        reply = there.bus.call(STOP, StopRequest(), timeout=10.0)
        print(f"\n{reply.to_json()}")
        assert (reply.playing, reply.stopped, reply.dropped) == (True, True, 2)
        assert reply.still and reply.phase == "trajectory"
        assert follower.dropped == 2
        time.sleep(1.0)  # nothing more plays
        assert there.sim_calls("angleInterpolation") == 1
        _assert_stopped_mid_way(there)
        there.bus.publish(TRAJECTORY_TOPIC, _reach(1.0))
        _wait("the one published after the stop", lambda: follower.played == 1)
        # its outcome is published before it counts as played, but it is
        # received on Zenoh's thread: a loaded machine delivers it later
        _wait("its outcome", lambda: len(there.outcomes) == 2)
        assert [o.outcome for o in there.outcomes] == ["stopped", "completed"]


def _armplan(*args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [sys.executable, "-m", "armplan", *args],
        capture_output=True,
        text=True,
        timeout=60,
        check=False,
        cwd=REPO,
    )


def test_armplan_stop_stops_the_arm_end_to_end(tmp_path: Path, sim: SimProcess) -> None:
    """``armplan stop --connect E --reason R`` during a trajectory: exit 0,
    it says what it stopped, and the arm holds still short of the end."""
    with served(tmp_path, sim) as there:
        running = there.execute_in_background(_reach(LONG))
        there.wait_for_state(0.8)
        endpoint = there.bus.config.endpoint
        done = _armplan("stop", "--connect", endpoint, "--reason", "from the CLI")
        print(f"\n{done.stdout}{done.stderr}")
        assert done.returncode == 0, done.stderr
        assert done.stdout.startswith("stopped the right arm's trajectory at t = ")
        assert "; the arm is still (answered in " in done.stdout
        running["thread"].join(10.0)
        assert running["error"].evidence["stop_reason"] == "from the CLI"
        _assert_stopped_mid_way(there)


def test_armplan_stop_without_a_bridge_is_a_clear_error(tmp_path: Path) -> None:
    """A router but no bridge: exit 1, naming the bridge that is not alive."""
    config = load_config(endpoints=(free_endpoint(),))
    with (
        (tmp_path / "router.log").open("w") as router_log,
        Launcher(config, [], log=router_log),
    ):
        done = _armplan("stop", "--connect", config.endpoint, "--timeout", "3")
    print(f"\n{done.stderr}")
    assert done.returncode == 1
    assert done.stdout == ""
    assert done.stderr.startswith("armplan: error: ")
    assert "bridge" in done.stderr and "armplan/bridge/stop" in done.stderr
    assert ServiceUnavailableError.kind == "service_unavailable"


def test_a_stop_too_short_to_wait_says_ordered_not_confirmed(
    tmp_path: Path, sim: SimProcess
) -> None:
    """``armplan stop --timeout 0.05`` during a trajectory: the arm is
    stopped; the reply, sent before the execution could end, says stopped
    (ordered) with the arm and phase, not ended, not known still; the CLI
    says so and exits 1."""
    with served(tmp_path, sim) as there:
        running = there.execute_in_background(_reach(LONG))
        there.wait_for_state(1.0)
        endpoint = there.bus.config.endpoint
        done = _armplan("stop", "--connect", endpoint, "--timeout", "0.05", "--json")
        print(f"\n{done.stdout}{done.stderr}")
        running["thread"].join(10.0)
        _assert_stopped_mid_way(there)
        if done.returncode == 1 and "did not answer" in done.stderr:
            pytest.skip("the CLI's 50 ms passed before the reply (a loaded machine)")
        reply = StopReply.model_validate_json(done.stdout)
        assert done.returncode == 1
        assert (reply.playing, reply.stopped, reply.ended, reply.still) == (
            True,
            True,
            False,
            False,
        )
        assert (reply.arm, reply.phase) == ("right", "trajectory")
        assert reply.phase_duration == pytest.approx(LONG, abs=0.05)
        assert "look at the robot" in done.stderr
        from armplan.cli.commands.stop import describe

        assert describe(reply).startswith(
            "ordered the right arm's movement stopped; not yet confirmed; "
            "the arm is NOT known still (answered in "
        )


def test_a_stop_with_nothing_playing_and_no_time_to_read_says_what_to_change(
    tmp_path: Path, sim: SimProcess
) -> None:
    """Nothing playing, ``armplan stop --timeout 0.05``: the bridge has no time
    to read the arm, so it is not known still (exit 1), and the CLI now says
    the timeout was the cause and what to give (it said only "look at the
    robot", alarming an e-stop script that set a tiny timeout); with the
    default timeout the same stop reads the arm still and exits 0."""
    with served(tmp_path, sim) as there:
        endpoint = there.bus.config.endpoint
        short = _armplan("stop", "--connect", endpoint, "--timeout", "0.05")
        enough = _armplan("stop", "--connect", endpoint)
    if short.returncode == 1 and "did not answer" in short.stderr:
        pytest.skip("the CLI's 50 ms passed before the reply (a loaded machine)")
    assert short.returncode == 1, short.stderr
    assert "nothing was playing; the arm is NOT known still" in short.stdout
    assert (
        "known still (--timeout 0.05 s left it no time to read the arm; give it "
        "more, e.g. the default 10 s): look at the robot"
    ) in short.stderr
    assert enough.returncode == 0, enough.stderr
    assert "the arm is still" in enough.stdout
    assert "--timeout" not in enough.stderr


def test_a_stop_with_the_robot_frozen_never_says_still(
    tmp_path: Path, sim: SimProcess
) -> None:
    """The sim frozen (SIGSTOP) 1 s into a 4 s trajectory: two stops at once
    and then ``armplan stop`` all say the arm is NOT known still (the bridge
    keeps stopping a call the robot did not answer), the CLI exits 1; the
    execute's error never says the arm stopped."""
    with served(tmp_path, sim) as there:
        running = there.execute_in_background(_reach(LONG))
        there.wait_for_state(1.0)
        os.kill(sim.pid, signal.SIGSTOP)
        try:
            replies: list[Any] = [None, None]

            def stop(i: int) -> None:
                replies[i] = there.bus.call(STOP, StopRequest(), timeout=10.0)

            both = [threading.Thread(target=stop, args=(i,)) for i in range(2)]
            for thread in both:
                thread.start()
            for thread in both:
                thread.join(15.0)
            print(f"\n{[r.to_json() for r in replies if r is not None]}")
            assert [getattr(r, "still", None) for r in replies] == [False, False]
            for reply in replies:
                assert isinstance(reply, StopReply)
                assert reply.playing and reply.note
            running["thread"].join(10.0)
            error = running["error"]
            print(error.message)
            assert "the arm stopped where it was then" not in error.message
            if error.kind == "robot_state":
                assert "the robot has not confirmed it" in error.message
            endpoint = there.bus.config.endpoint
            done = _armplan("stop", "--connect", endpoint)
            print(f"{done.stdout}{done.stderr}")
            assert done.returncode == 1
            assert "the arm is NOT known still" in done.stdout
            assert "look at the robot" in done.stderr
        finally:
            os.kill(sim.pid, signal.SIGCONT)


def test_armplan_stop_cuts_a_long_reason_instead_of_refusing(
    tmp_path: Path, sim: SimProcess
) -> None:
    """``--reason`` of 261 characters with a line break, and an empty one:
    the stop is sent all the same (exit 0, nothing playing, the arm read
    still), the reason cleaned and cut to 200, with warnings."""
    with served(tmp_path, sim) as there:
        endpoint = there.bus.config.endpoint
        long = "x" * 130 + "\n" + "y" * 130
        done = _armplan("stop", "--connect", endpoint, "--reason", long, "--json")
        print(f"\n{done.stdout}{done.stderr}")
        assert done.returncode == 0, done.stderr
        reply = StopReply.model_validate_json(done.stdout)
        assert reply.reason == ("x" * 130 + " " + "y" * 130)[:200]
        assert reply.still and not reply.playing
        assert "warning: the reason was cut to 200 of its 261 characters" in (
            done.stderr
        )
        assert "warning: 1 control character in the reason was removed" in done.stderr
        empty = _armplan("stop", "--connect", endpoint, "--reason", "")
        assert empty.returncode == 0, empty.stderr
        assert empty.stdout.startswith("nothing was playing; the arm is still")
        assert "warning: the reason is empty" in empty.stderr


def test_a_burst_of_stops_is_never_answered_busy(
    tmp_path: Path, sim: SimProcess
) -> None:
    """120 stops at once, the bridge's queue limit 4: every one is answered
    with a StopReply (none ``service_busy``), all saying the same."""
    from concurrent.futures import ThreadPoolExecutor

    with served(tmp_path, sim, queue_limit=4) as there:
        with ThreadPoolExecutor(40) as pool:
            calls = [
                pool.submit(there.bus.call, STOP, "{}", timeout=10.0)
                for _ in range(120)
            ]
            replies = [call.result(20.0) for call in calls]
        assert {(r.playing, r.stopped, r.still) for r in replies} == {
            (False, False, True)
        }


def test_an_execute_query_queued_before_a_stop_is_stopped_too(
    tmp_path: Path, sim: SimProcess
) -> None:
    """A second execute query waits in the queue (the one worker plays the
    first) when the operator's stop comes: the stop meant it too. It is
    refused "stopped", nothing of it sent (it played after the stop, the
    arm moving while ``armplan stop`` had said it was still)."""
    with served(tmp_path, sim) as there:
        first = there.execute_in_background(_reach(LONG))
        there.wait_for_state(0.8)
        queued = there.execute_in_background(_reach(1.0))
        time.sleep(0.5)  # it has arrived, and waits for the worker
        reply = there.bus.call(STOP, StopRequest(reason="e-stop"), timeout=10.0)
        print(f"\n{reply.to_json()}")
        first["thread"].join(10.0)
        queued["thread"].join(10.0)
        assert (reply.playing, reply.stopped, reply.still) == (True, True, True)
        assert first["error"].evidence["stopped_by"] == "bridge/stop"
        error = queued.get("error")
        assert error is not None, queued.get("reply")
        print(error.message)
        assert error.evidence["stopped_by"] == "bridge/stop"
        assert error.evidence["stop_reason"] == "e-stop"
        assert "nothing was sent" in str(error.evidence.get("outcome", ""))
        time.sleep(0.5)
        assert there.sim_calls("angleInterpolation") == 1  # the first alone
        _assert_stopped_mid_way(there)
        _wait("two outcomes", lambda: len(there.outcomes) == 2)
        assert [o.outcome for o in there.outcomes] == ["stopped", "stopped"]


def test_an_oversized_stop_is_answered_and_the_next_reply_is_its_own(
    tmp_path: Path, sim: SimProcess
) -> None:
    """A stop whose payload is over the bridge's size limit stops the arm
    and gets a StopReply (never payload_too_large); a stop whose reply was
    never built (ordered, then its query lost) is not reported by the next
    stop's reply: that one says only what it found (nothing playing)."""
    from shared.bus.arrival import arrived_at

    limit = len(ExecuteRequest(trajectory=_reach(LONG)).to_json()) + 100
    with served(tmp_path, sim, max_payload=limit) as there:
        running = there.execute_in_background(_reach(LONG))
        there.wait_for_state(0.8)
        big = '{"reason": "' + "x" * limit + '"}'
        reply = there.bus.call(STOP, big, timeout=10.0)
        print(f"\n{reply.to_json()}")
        running["thread"].join(10.0)
        assert (reply.playing, reply.stopped, reply.still) == (True, True, True)
        _assert_stopped_mid_way(there)
        running = there.execute_in_background(_reach(1.0))  # back to rest
        running["thread"].join(15.0)
        assert "reply" in running, running.get("error")
        # a stop ordered on the bridge whose answer never runs
        with arrived_at(time.monotonic()):
            there.service.order_stop(b'{"reason": "lost"}')
        time.sleep(0.2)
        reply = there.bus.call(STOP, "{}", timeout=10.0)
        print(reply.to_json())
        assert (reply.playing, reply.stopped, reply.still) == (False, False, True)
        assert reply.reason is None and reply.waited < 0.5 and reply.arm is None


def test_a_stop_is_answered_when_the_next_trajectory_takes_the_robot(
    tmp_path: Path, sim: SimProcess
) -> None:
    """``--follow``: a trajectory published right after the stop takes the
    robot as soon as the stopped one gives it back, before the reply looks
    (its thread run 0.6 s late, as on a loaded machine). Published from that
    thread: one published by the caller just after asking may arrive first,
    and is then rightly dropped by the stop (as CI once saw). The reply does not wait
    for it to end (nor for HALT_END_WAIT): it comes at once, says the
    stopped trajectory was stopped, and that the arm is not still (the new
    one is playing)."""
    from bridge.stop_desk import HALT_END_WAIT

    with served(tmp_path, sim, follow=True) as there:
        follower = there.follower
        assert follower is not None
        there.bus.publish(TRAJECTORY_TOPIC, _reach(LONG))
        there.wait_for_state(0.8)
        slot = there.service._slot
        wait_free = slot.wait_free

        following = _reach(1.0)
        published: list[float] = []

        def late(*args: Any, **kwargs: Any) -> Any:  # a reply thread run late
            if not published:  # the next, right after the stop dropped
                published.append(time.monotonic())  # what waited
                there.bus.publish(TRAJECTORY_TOPIC, following)
            time.sleep(0.6)  # (a loaded machine): the next has taken the robot
            return wait_free(*args, **kwargs)

        slot.wait_free = late  # type: ignore[method-assign]
        asked = time.monotonic()
        replies = there.bus.session.get(
            STOP.key(there.bus.config.namespace), payload=b"{}", timeout=10.0
        )
        answers = list(replies)
        took = time.monotonic() - asked
        assert len(answers) == 1 and answers[0].ok is not None
        reply = StopReply.model_validate_json(answers[0].ok.payload.to_bytes())
        print(f"\n{reply.to_json()} in {took:.2f} s")
        assert (reply.playing, reply.stopped, reply.ended) == (True, True, True)
        assert reply.phase == "trajectory" and reply.dropped == 0
        assert not reply.still
        assert reply.note is not None and "after the stop is playing" in reply.note
        assert took < 1.0 < HALT_END_WAIT
        _wait("the one published after the stop", lambda: follower.played == 1)
        _wait("its outcome", lambda: len(there.outcomes) == 2)
        assert [o.outcome for o in there.outcomes] == ["stopped", "completed"]


def test_a_stop_answered_before_the_call_arrived_confirms_nothing(
    tmp_path: Path, sim: SimProcess
) -> None:
    """A stop while a 4 s call at 1000 fps is still on its way over an 80 kB/s
    link: the robot answers the kill at once, but that ends nothing (the
    call has not arrived). The caller is told the stop was sent, not
    confirmed (it was told "the arm stopped where it was then" while the
    stopper was still at work); the reply does not say the arm is still;
    the call is ended as it takes effect."""
    from tests.slow_link import SlowLink

    link = SlowLink(int(sim.url.rsplit(":", 1)[1]), 80e3)
    try:
        with served(tmp_path, sim, url=link.url) as there:
            running = there.execute_in_background(_reach(LONG), rate=1000.0)

            def on_its_way() -> bool:
                serving = there.service._slot.serving
                return serving is not None and serving.sent is not None

            # no approach; the checks and the stiffening take longer on a
            # loaded machine: the stop must come once the call has left
            _wait("the trajectory's call leaves", on_its_way)
            time.sleep(0.2)  # on its way: about 2 s over this link
            assert there.sim_calls("angleInterpolation") == 0
            reply = there.bus.call(STOP, StopRequest(), timeout=10.0)
            print(f"\n{reply.to_json()}")
            running["thread"].join(10.0)
            error = running["error"]
            print(error.message)
            assert error.evidence["stopped_by"] == "bridge/stop"
            assert "the stop was sent; the robot has not confirmed it" in str(
                error.evidence["outcome"]
            )
            assert "the arm stopped where it was then" not in error.message
            assert reply.stopped and not reply.still
            assert there.service.robot.client.wait_stopped()
            assert there.sim_calls("killTasksUsingResources") >= 1
    finally:
        link.close()


def test_armplan_stop_is_sent_even_without_the_bridges_token(tmp_path: Path) -> None:
    """A queryable on ``bridge/stop`` whose liveliness token is not seen
    (a bridge that lost it): ``armplan stop`` sends the stop all the same
    and prints its answer; it used to refuse to send it at all."""
    config = load_config(endpoints=(free_endpoint(),))
    asked: list[bytes] = []
    answer = StopReply(playing=False, stopped=False, dropped=0, still=True, waited=0)

    def serve(query: zenoh.Query) -> None:
        payload = query.payload
        asked.append(b"" if payload is None else payload.to_bytes())
        with query:
            query.reply(query.key_expr, answer.to_json())

    with (
        (tmp_path / "router.log").open("w") as router_log,
        Launcher(config, [], log=router_log),
        Bus.connect(config) as bus,
    ):
        queryable = bus.session.declare_queryable(bus.key(STOP.path), serve)
        try:
            assert BRIDGE not in bus.alive()
            done = _armplan("stop", "--connect", config.endpoint, "--reason", "r")
        finally:
            queryable.undeclare()  # type: ignore[no-untyped-call]
    print(f"\n{done.stdout}{done.stderr}")
    assert done.returncode == 0, done.stderr
    assert done.stdout.startswith("nothing was playing; the arm is still")
    assert len(asked) == 1 and b'"r"' in asked[0]


def test_a_stop_reads_every_arm_an_error_left_unsure(
    tmp_path: Path, sim: SimProcess
) -> None:
    """Executions on the left arm, then on the right, ended with an error
    mid-movement: a stop with nothing playing says "still" only once BOTH
    arms read settled. The left arm moving (another client's call) keeps it
    from saying so; once the left is still, it does, and forgets both."""
    left = list(Side.LEFT.joint_names)
    with served(tmp_path, sim) as there:
        desk = there.service._desk
        desk.mark_unsure("left")
        desk.mark_unsure("right")
        away = [-0.5, 0.2, 0.3, -0.3, 0.3]  # [rad] within the left arm's ranges
        target = [float(a) + d for a, d in zip(rest("left"), away, strict=True)]
        moving = there._motion.angleInterpolation(left, target, 1.5, True, _async=True)
        time.sleep(0.3)  # the left arm under way
        reply = there.service.halt(StopRequest(reason="test"))
        assert reply.still is False, reply.to_json()
        assert reply.note is not None and "settle" in reply.note
        moving.value(10000)  # [ms] the left arm's call has ended
        reply = there.service.halt(StopRequest(reason="test"))
        assert reply.still is True, reply.to_json()
        assert desk._unsure == {}


def test_an_outcome_put_that_waits_does_not_hold_the_stop_reply(
    tmp_path: Path, sim: SimProcess, monkeypatch: pytest.MonkeyPatch
) -> None:
    """``bridge/outcome`` is put with Zenoh's BLOCK, which waits up to 5 s
    for room when a subscriber stopped reading (a recorder suspended with
    Ctrl-Z). A stopped execution published its outcome before freeing the
    robot, which the stop's reply waits for (3.25 s at most): the reply
    said "not yet confirmed", not still, though the arm had stopped at once."""
    with served(tmp_path, sim) as there:
        bridge_bus, publish = there.service.bus, there.service.bus.publish

        def put_waiting_for_room(path: str, message: Any) -> None:
            if path == BRIDGE_OUTCOME_TOPIC:
                time.sleep(5.0)  # BLOCK's longest wait before the link closes
            publish(path, message)

        monkeypatch.setattr(bridge_bus, "publish", put_waiting_for_room)
        running = there.execute_in_background(_reach(LONG))
        there.wait_for_state(1.0)
        asked = time.monotonic()
        reply = there.bus.call(STOP, StopRequest(reason="test"), timeout=10.0)
        took = time.monotonic() - asked
        running["thread"].join(15.0)
        assert (reply.stopped, reply.still, reply.phase) == (True, True, "trajectory")
        assert took < 2.5
        _wait("the outcome", lambda: len(there.outcomes) == 1)
