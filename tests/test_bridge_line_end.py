"""How ``python -m bridge`` (the bridge on stdin/stdout) ends: at the end
of its input, or told to stop by a signal, as ``python -m bridge.serve``.

Real processes: the bridge as a subprocess reading JSON lines, the
simulated NAO as its own process over libqi (paused with SIGSTOP where a
robot must go silent), and real signals sent to the bridge. Where the
stop's 30 s limit must be shorter, the bridge's line loop runs in this
process (``bridge.__main__.serve`` on a pipe, the real sim), its stop
given the shorter limit.
"""

from __future__ import annotations

import io
import json
import os
import queue
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

from bridge.__main__ import serve
from bridge.minimum_jerk import minimum_jerk_trajectory
from bridge.naoqi_client import NaoqiClient
from bridge.robot_bridge import RobotBridge
from bridge.sim import SimProcess
from bridge.stopping import CUT_WAIT
from shared.messages import ExecuteReply, ExecuteRequest, Trajectory
from shared.robot.postures import forward, rest
from tests.test_bridge_watch import (
    AWAY,
    finished,
    last_moved,
    sim_events,
    when_sim_logs,
)


class LineBridge:
    """``python -m bridge ARGS``: JSON lines in and out, stderr to a file."""

    def __init__(
        self, *args: str, log: Path, env: dict[str, str] | None = None
    ) -> None:
        self.log = log
        with log.open("w") as stderr:
            self.process = subprocess.Popen(
                [sys.executable, "-m", "bridge", *args],
                stdin=subprocess.PIPE,
                stdout=subprocess.PIPE,
                stderr=stderr,
                text=True,
                env=env,
            )
        self.lines: queue.Queue[str] = queue.Queue()
        threading.Thread(target=self._read, daemon=True).start()

    def _read(self) -> None:
        assert self.process.stdout is not None
        for line in self.process.stdout:
            self.lines.put(line)

    def send(self, request: ExecuteRequest) -> None:
        assert self.process.stdin is not None
        self.process.stdin.write(request.to_json() + "\n")
        self.process.stdin.flush()

    def reply(self, timeout: float = 30.0) -> dict[str, Any]:
        return dict(json.loads(self.lines.get(timeout=timeout)))

    def end_input(self) -> None:
        assert self.process.stdin is not None
        self.process.stdin.close()

    def wait(self, timeout: float) -> int | None:
        """The exit code, or None if it still runs after ``timeout`` [s]."""
        try:
            return self.process.wait(timeout)
        except subprocess.TimeoutExpired:
            return None

    def close(self) -> None:
        if self.process.poll() is None:
            self.process.kill()
            self.process.wait(10)
        if self.process.stdin is not None and not self.process.stdin.closed:
            self.process.stdin.close()


@pytest.fixture
def started(tmp_path: Path) -> Iterator[list[LineBridge]]:
    """Every bridge a test starts, killed at its end if still running."""
    bridges: list[LineBridge] = []
    try:
        yield bridges
    finally:
        for bridge in bridges:
            bridge.close()


def reach(duration: float) -> Trajectory:
    """Rest to away and back, ``duration`` [s] each way: no approach."""
    return minimum_jerk_trajectory(
        "right", [rest("right"), AWAY, rest("right")], [duration, duration]
    )


def test_a_bridge_whose_input_ends_waits_for_the_stops_of_a_robot_given_up(
    tmp_path: Path, sim: SimProcess, started: list[LineBridge]
) -> None:
    """The sim paused (SIGSTOP) 1 s into a 10 s trajectory, stdin ended: the
    bridge answers robot_unavailable ("keeps stopping the arm until the call
    ends"), and exits only once it has: 0, after the sim resumed, the call
    ended by killTasksUsingResources. It used to exit at once, while the sim
    was paused, often crashing in libqi (exit 134 or 139): the stops it
    promised were never sent and the arm played on."""
    bridge = LineBridge("--robot", sim.url, log=tmp_path / "bridge.log")
    started.append(bridge)
    bridge.send(ExecuteRequest(trajectory=reach(5.0)))
    bridge.end_input()
    began = when_sim_logs(sim, "motion", "angleInterpolation")
    time.sleep(max(0.0, began + 1.0 - time.monotonic()))
    os.kill(sim.pid, signal.SIGSTOP)
    try:
        error = bridge.reply(timeout=10.0)["error"]
        assert error["kind"] == "robot_unavailable", error
        assert "keeps stopping the arm until the call ends" in error["message"]
        assert bridge.wait(3.0) is None  # still stopping the arm
    finally:
        os.kill(sim.pid, signal.SIGCONT)
    code = bridge.wait(10.0)
    stderr = bridge.log.read_text()
    assert code == 0, stderr
    assert "Traceback" not in stderr and "the robot go" not in stderr
    ended = [e for e in sim_events(sim, "done", "interrupted") if e["at"] > began]
    assert [e["event"] for e in ended] == ["interrupted"], ended
    assert "killTasksUsingResources" in ended[0]["reason"]


def _calls(sim: SimProcess, method: str) -> list[dict[str, Any]]:
    return [e for e in sim_events(sim, "call") if e["method"] == method]


@pytest.mark.parametrize(
    "signum", [signal.SIGINT, signal.SIGTERM, signal.SIGHUP], ids=lambda s: s.name
)
def test_a_stop_signal_lets_the_trajectory_playing_end_watched(
    tmp_path: Path, sim: SimProcess, started: list[LineBridge], signum: int
) -> None:
    """The signal 1 s into a 4 s trajectory, stdin left open: the trajectory
    plays to its end, watched, its reply line is written, and the bridge
    exits 0 without reading on. It used to die at once (Ctrl-C: a
    traceback, exit 130; SIGTERM: exit 143), with no reply line, the arm
    playing on with nobody watching."""
    bridge = LineBridge("--robot", sim.url, log=tmp_path / "bridge.log")
    started.append(bridge)
    bridge.send(ExecuteRequest(trajectory=reach(2.0)))
    began = when_sim_logs(sim, "motion", "angleInterpolation")
    time.sleep(max(0.0, began + 1.0 - time.monotonic()))
    bridge.process.send_signal(signum)
    line = bridge.reply(timeout=10.0)
    code = bridge.wait(5.0)
    stderr = bridge.log.read_text()
    assert code == 0, stderr
    assert "Traceback" not in stderr
    reply = ExecuteReply.model_validate(line)
    assert reply.report.duration >= 4.0 - 2.0 * reply.report.sample_period
    assert finished(sim) == ["done"]  # played to its last key
    assert _calls(sim, "killTasksUsingResources") == []
    assert bridge.lines.empty()


def test_a_stop_signal_in_the_approach_sends_no_trajectory(
    tmp_path: Path, sim: SimProcess, started: list[LineBridge]
) -> None:
    """SIGTERM as the approach to a trajectory starts: the approach ends,
    the trajectory is not sent, its line says so, and the bridge exits 0."""
    bridge = LineBridge("--robot", sim.url, log=tmp_path / "bridge.log")
    started.append(bridge)
    trajectory = minimum_jerk_trajectory(
        "right", [forward("right"), rest("right")], [2.0]
    )
    bridge.send(ExecuteRequest(trajectory=trajectory))
    when_sim_logs(sim, "motion", "angleInterpolation")  # the approach
    bridge.process.send_signal(signal.SIGTERM)
    error = bridge.reply(timeout=10.0)["error"]
    assert bridge.wait(5.0) == 0, bridge.log.read_text()
    assert error["kind"] == "service_unavailable"
    assert error["message"].endswith(
        "the bridge is stopping; the arm is at the trajectory's start; nothing "
        "of the trajectory was sent"
    )
    assert len(_calls(sim, "angleInterpolation")) == 1  # the approach alone


def test_a_stop_signal_with_nothing_playing_ends_the_bridge_at_once(
    tmp_path: Path, sim: SimProcess, started: list[LineBridge]
) -> None:
    """Ctrl-C between two requests: exit 0 at once, no line, no traceback."""
    bridge = LineBridge("--robot", sim.url, log=tmp_path / "bridge.log")
    started.append(bridge)
    hold = minimum_jerk_trajectory("right", [rest("right")] * 2, [0.5])
    bridge.send(ExecuteRequest(trajectory=hold))
    ExecuteReply.model_validate(bridge.reply(timeout=10.0))
    bridge.process.send_signal(signal.SIGINT)
    assert bridge.wait(2.0) == 0
    assert "Traceback" not in bridge.log.read_text()
    assert bridge.lines.empty()


def test_a_stop_that_cannot_wait_for_the_end_stops_the_arm_and_says_so(
    sim: SimProcess,
) -> None:
    """The line loop told to stop 0.5 s into a 4 s trajectory, its limit
    1 s (30 s in the process): the arm's motion tasks are stopped, the line
    says "the bridge is stopping; it stopped the arm at about t = ...", and
    the loop returns without answering the next line."""
    read_end, write_end = os.pipe()
    source = os.fdopen(read_end, "r", encoding="utf-8")
    feed = os.fdopen(write_end, "w", encoding="utf-8", buffering=1)
    sink = io.StringIO()
    stop = threading.Event()
    trajectory = minimum_jerk_trajectory(
        "right", [rest("right"), forward("right")], [4.0]
    )
    with NaoqiClient(sim.url) as client:
        loop = threading.Thread(
            target=serve, args=(RobotBridge(client), source, sink, stop, 1.0)
        )
        loop.start()
        feed.write(ExecuteRequest(trajectory=trajectory).to_json() + "\n")
        began = when_sim_logs(sim, "motion", "angleInterpolation")
        time.sleep(max(0.0, began + 0.5 - time.monotonic()))
        stop.set()
        loop.join(10.0)
        assert not loop.is_alive()
        feed.write(ExecuteRequest(trajectory=trajectory).to_json() + "\n")
        time.sleep(0.5)  # time enough to refuse it, were it read
    feed.close()
    source.close()
    lines = sink.getvalue().splitlines()
    assert len(lines) == 1, lines
    error = json.loads(lines[0])["error"]
    assert error["kind"] == "service_unavailable"
    found = re.search(
        r"the bridge is stopping; it stopped the arm at about t = (\d+\.\d) s of "
        r"4\.00 s \(its movement would end past the 1 s a stopping bridge waits "
        r"for it\): stopped it",
        error["message"],
    )
    assert found is not None, error["message"]
    assert 1.3 <= float(found.group(1)) <= 1.5 + CUT_WAIT
    kill = float(_calls(sim, "killTasksUsingResources")[0]["at"])
    time.sleep(max(0.0, began + 4.2 - time.monotonic()))  # the unstopped end
    assert last_moved(sim) < kill + 0.05
    assert finished(sim) == []
    assert len(_calls(sim, "angleInterpolation")) == 1
