"""How ``python -m bridge`` (the bridge on stdin/stdout) ends.

Real processes: the bridge as a subprocess reading JSON lines, the
simulated NAO as its own process over libqi (paused with SIGSTOP where a
robot must go silent), and real signals sent to the bridge.
"""

from __future__ import annotations

import json
import os
import queue
import signal
import subprocess
import sys
import threading
import time
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest

from bridge.minimum_jerk import minimum_jerk_trajectory
from bridge.sim import SimProcess
from shared.messages import ExecuteRequest, Trajectory
from shared.robot.postures import rest
from tests.test_bridge_watch import AWAY, sim_events, when_sim_logs


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
