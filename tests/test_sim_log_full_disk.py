"""A sim log that cannot be written does not fail the sim's ALMotion calls.

On a full disk the sim's log raised inside angleInterpolation, the call
failed with "[Errno 28] No space left on device", and the bridge said the
motion task was killed by killAll or another client. Real parts: a sim
child process whose file size limit (RLIMIT_FSIZE, EFBIG past it) stops
its log a few lines in, a trajectory played on it over libqi.
"""

from __future__ import annotations

import resource
import time
from pathlib import Path

import pytest

from bridge.minimum_jerk import minimum_jerk_trajectory
from bridge.naoqi_client import NaoqiClient
from bridge.playback import _ended_early
from bridge.robot_bridge import RobotBridge
from bridge.sim import SimProcess
from shared.robot.postures import forward, rest

#: Bytes the log may grow by once the limit is set: a few lines.
ROOM = 2000


def test_a_full_log_leaves_the_motion_played_and_says_so_once(
    tmp_path: Path, sim: SimProcess
) -> None:
    assert sim.log_path is not None
    size = sim.log_path.stat().st_size
    hard = resource.getrlimit(resource.RLIMIT_FSIZE)[1]
    resource.prlimit(sim.pid, resource.RLIMIT_FSIZE, (size + ROOM, hard))
    trajectory = minimum_jerk_trajectory(
        "right", [rest("right"), forward("right")], [1.0]
    )
    robot = RobotBridge(NaoqiClient(sim.url))
    try:
        reply = robot.execute(trajectory)  # raised RobotStateError
    finally:
        robot.client.close()
    assert reply.report.samples > 0
    assert sim.log_path.stat().st_size <= size + ROOM
    time.sleep(0.2)  # the sim's output is read by a thread
    warnings = [line for line in sim.output if "stopped writing the sim log" in line]
    assert len(warnings) == 1
    assert str(sim.log_path) in warnings[0]


@pytest.mark.parametrize(
    ("failed", "killed"),
    [
        ("[Errno 28] No space left on device", False),
        ("angleInterpolation was interrupted: killAll", True),
        (None, True),
    ],
)
def test_only_a_kill_is_said_to_be_one(
    sim: SimProcess, failed: str | None, killed: bool
) -> None:
    """A call that failed for another reason is said as it failed."""
    client = NaoqiClient(sim.url)
    try:
        ended = time.monotonic()
        error = _ended_early(client, ["RShoulderPitch"], 0.5, 1.0, failed, ended)
    finally:
        client.close()
    assert ("motion task was killed" in error.message) is killed
    assert error.stopped_at == ended
    if failed is not None:
        assert f'its call failed ("{failed}") before its last key' in error.message
