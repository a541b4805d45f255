"""The bridge process against the simulated NAO process, over real libqi.

The bridge runs as its own process (``python -m bridge``, requests and
replies as JSON lines), as it does in the system, and reaches the simulated
NAO (``python -m bridge.sim``) through a real libqi session on 127.0.0.1:
refusal before sending, tracking within 1 degree RMS, the approach move, a
robot killed mid-trajectory (typed error within 2 s) and the reconnection
when it comes back at the same address.
"""

from __future__ import annotations

import json
import queue
import subprocess
import sys
import threading
import time
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from bridge.minimum_jerk import minimum_jerk_trajectory
from bridge.sim import SimProcess
from bridge.sim.log import read_log
from bridge.velocity_agreement import positions_slopes
from services.planner.pipeline import plan
from shared.messages import (
    ExecuteReply,
    ExecuteRequest,
    PlanRequest,
    Trajectory,
    parse,
)
from shared.robot import load_arm
from shared.robot.postures import rest


def realistic(rng: np.random.Generator, side: str = "right") -> Trajectory:
    """Rest -> reach -> hand over -> rest: seeded minimum-jerk segments at a
    human pace (0.8-1.0 s each), every posture inside the joint ranges."""
    limits = load_arm(side).limits
    inner = (limits.lower + 0.15 * limits.span, limits.upper - 0.15 * limits.span)
    targets = rng.uniform(*inner, (2, 5))
    return minimum_jerk_trajectory(
        side, [rest(side), *targets, rest(side)], [1.0, 0.8, 1.0]
    )


def with_sample(
    trajectory: Trajectory, index: int, joint: int, offset: float
) -> Trajectory:
    """``trajectory`` with one sample moved by ``offset`` [rad], its velocities
    those of the moved positions (their own curve's slopes), so that the jump
    is one the trajectory asks for, not velocities that disagree with it."""
    positions = np.asarray(trajectory.positions)
    positions[index, joint] += offset
    slopes = positions_slopes(np.asarray(trajectory.times), positions)
    return trajectory.model_copy(
        update={"positions": positions.tolist(), "velocities": slopes.tolist()}
    )


class BridgeProcess:
    """``python -m bridge --robot URL``, one JSON line in, one out.

    Every stdout line must be a reply: libqi's own log lines once came first
    on stdout, and a reader had to skip them.
    """

    def __init__(self, robot: str) -> None:
        self.process = subprocess.Popen(
            [sys.executable, "-m", "bridge", "--robot", robot],
            stdin=subprocess.PIPE,
            stdout=subprocess.PIPE,
            stderr=subprocess.DEVNULL,
            text=True,
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
        return json.loads(self.lines.get(timeout=timeout))

    def execute(self, request: ExecuteRequest) -> dict[str, Any]:
        self.send(request)
        return self.reply()

    def close(self) -> None:
        if self.process.stdin is not None:
            self.process.stdin.close()
        try:
            self.process.wait(10)
        except subprocess.TimeoutExpired:
            self.process.kill()
            self.process.wait(5)


@pytest.fixture
def bridge(sim: SimProcess) -> Iterator[BridgeProcess]:
    process = BridgeProcess(sim.url)
    try:
        yield process
    finally:
        process.close()


def commands_logged(sim: SimProcess) -> list[dict[str, Any]]:
    assert sim.log_path is not None
    return [e for e in read_log(sim.log_path) if e["event"] in ("call", "motion")]


def test_an_over_speed_trajectory_never_reaches_the_robot(
    sim: SimProcess, bridge: BridgeProcess, rng: np.random.Generator
) -> None:
    """One frame over RElbowYaw's speed limit: refused with joint, frame, time
    and limit; the simulated NAO's log shows no command at all."""
    bad = with_sample(realistic(rng), 48, 2, 0.4)
    error = bridge.execute(ExecuteRequest(trajectory=bad))["error"]
    assert error["kind"] == "trajectory_refused"
    assert "RElbowYaw speed" in error["message"]
    assert "frame 12 (t = 0.480 s)" in error["message"]
    assert "exceeds its limit 8.268 rad/s" in error["message"]
    assert (
        error["evidence"]["frame"] == 12 and error["evidence"]["joint"] == "RElbowYaw"
    )
    time.sleep(0.1)
    assert commands_logged(sim) == []


def test_frames_too_sparse_for_the_movement_never_reach_the_robot(
    sim: SimProcess, bridge: BridgeProcess, rng: np.random.Generator
) -> None:
    """At 2 frames a second the keys keep every limit, but the robot would cut
    the movement short: refused naming the joint and a rate that would do."""
    request = ExecuteRequest(trajectory=realistic(rng), rate=2.0)
    error = bridge.execute(request)["error"]
    assert error["kind"] == "trajectory_refused"
    assert error["evidence"]["quantity"] == "frame_rate"
    assert "between frames at 2 Hz (at most 1 deg): at " in error["message"]
    time.sleep(0.1)
    assert commands_logged(sim) == []


def test_velocities_that_disagree_with_the_positions_never_reach_the_robot(
    sim: SimProcess, bridge: BridgeProcess
) -> None:
    """A planned reach slowed 20 times by its times alone (the velocities
    left): its frames keep every limit and follow the curve through the
    velocities, which strays 2.7 degrees from the positions. The bridge
    played it; now it is refused naming the joint and the sample, and the
    simulated NAO's log shows no command."""
    request = parse(PlanRequest, {"targets": [{"position": [0.15, -0.1, 0.05]}]})
    reach = plan(request).trajectory
    slowed = reach.model_copy(update={"times": [20.0 * t for t in reach.times]})
    error = bridge.execute(ExecuteRequest(trajectory=slowed))["error"]
    assert error["kind"] == "trajectory_refused"
    assert error["evidence"]["quantity"] == "velocities"
    assert error["evidence"]["joint"] == "RShoulderPitch"
    assert error["evidence"]["frame"] == 37
    assert error["message"].startswith(
        "trajectory refused, nothing was sent: RShoulderPitch velocity -2.607 "
        "rad/s at sample 37 (t = 7.400 s) disagrees with the positions"
    )
    time.sleep(0.1)
    assert commands_logged(sim) == []


def test_the_simulated_nao_tracks_within_one_degree_rms(
    sim: SimProcess, bridge: BridgeProcess, rng: np.random.Generator
) -> None:
    """On a realistic trajectory, measured angles (getAngles, sampled at 100 Hz
    during execution) stay within 1 degree RMS of the trajectory, per joint."""
    trajectory = realistic(rng)
    reply = ExecuteReply.model_validate(
        bridge.execute(ExecuteRequest(trajectory=trajectory))
    )
    report = reply.report
    print(
        "\ntracking RMS [deg]:",
        {k: round(v, 3) for k, v in report.tracking_rms_deg.items()},
    )
    print(
        "tracking max [deg]:",
        {k: round(v, 3) for k, v in report.tracking_max_deg.items()},
    )
    print(f"compared {report.samples}, left out {report.discarded} slow readings")
    assert reply.approach_duration == 0.0 and reply.frames == 70
    assert report.samples + report.discarded == len(reply.states.times)
    # about 190 readings usually; 71 (49 trusted) once when the machine was slow
    assert report.samples >= 30 and report.time_uncertainty <= 0.05
    assert len(reply.states.round_trips) == len(reply.states.times)
    assert report.duration == pytest.approx(trajectory.duration, abs=0.1)
    for joint in trajectory.joint_names:
        assert report.tracking_rms_deg[joint] < 1.0
    assert sim.log_path is not None
    assert not [e for e in read_log(sim.log_path) if e["event"] == "refused"]


def test_an_arm_elsewhere_is_brought_to_the_start_first(
    bridge: BridgeProcess, rng: np.random.Generator
) -> None:
    """A trajectory starting away from the arm: a slow approach, then tracking;
    with the approach off, it is refused before anything moves."""
    limits = load_arm("right").limits
    start = rng.uniform(
        limits.lower + 0.2 * limits.span, limits.upper - 0.2 * limits.span
    )
    trajectory = minimum_jerk_trajectory("right", [start, rest("right")], [0.9])
    refused = bridge.execute(ExecuteRequest(trajectory=trajectory, approach=False))
    assert "the approach move is off" in refused["error"]["message"]
    reply = ExecuteReply.model_validate(
        bridge.execute(ExecuteRequest(trajectory=trajectory))
    )
    assert reply.approach_duration >= 0.5
    assert max(reply.report.tracking_rms_deg.values()) < 1.0


def test_a_robot_killed_mid_trajectory_gives_a_typed_error_within_2_s(
    tmp_path: Path, rng: np.random.Generator
) -> None:
    """SIGKILL the sim 0.5 s into a 2.8 s trajectory: robot_unavailable within
    2 s; the same bridge process picks up a new sim at the same address."""
    first = SimProcess(log_path=tmp_path / "first.jsonl")
    url = first.start()
    second = SimProcess(listen=url, log_path=tmp_path / "second.jsonl")
    bridge = BridgeProcess(url)
    request = ExecuteRequest(trajectory=realistic(rng))
    try:
        bridge.send(request)
        time.sleep(0.5)
        killed_at = time.monotonic()
        first.kill()
        reply = bridge.reply(timeout=5.0)
        delay = reply["at"] - killed_at
        print(
            f"\nerror {delay * 1000:.1f} ms after the kill: {reply['error']['message']}"
        )
        assert reply["error"]["kind"] == "robot_unavailable"
        assert reply["error"]["evidence"]["url"] == url
        assert 0.0 < delay < 2.0
        absent = bridge.execute(request)["error"]
        assert (
            absent["kind"] == "robot_unavailable"
            and "Connection refused" in absent["message"]
        )
        second.start()
        again = ExecuteReply.model_validate(bridge.execute(request))
        assert max(again.report.tracking_rms_deg.values()) < 1.0
        assert bridge.process.poll() is None
    finally:
        bridge.close()
        first.stop()
        second.stop()


def test_a_trajectory_of_no_joints_is_refused_and_the_next_one_plays(
    bridge: BridgeProcess,
) -> None:
    """joint_names [] (and rows of nothing): invalid_input naming the field;
    the same bridge process plays the next request (it used to exit)."""
    hold = minimum_jerk_trajectory("right", [rest("right"), rest("right")], [0.5])
    empty = hold.model_dump(mode="json")
    empty.update(
        joint_names=[],
        positions=[[] for _ in hold.times],
        velocities=[[] for _ in hold.times],
        accelerations=[[] for _ in hold.times],
    )
    bridge.process.stdin.write(json.dumps({"trajectory": empty}) + "\n")  # type: ignore[union-attr]
    bridge.process.stdin.flush()  # type: ignore[union-attr]
    error = bridge.reply()["error"]
    assert error["kind"] == "invalid_input"
    assert error["evidence"]["field"] == "trajectory.joint_names"
    reply = ExecuteReply.model_validate(bridge.execute(ExecuteRequest(trajectory=hold)))
    assert reply.frames > 0 and bridge.process.poll() is None
