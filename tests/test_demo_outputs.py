"""The demo's four outputs are written as a set, each failure naming its file.

A SIGTERM (or a failed write) while they were written left a behavior.xar
without the trajectory and report it came with. Real parts: a reach played
on the simulated NAO over libqi, then written into a real folder.
"""

from __future__ import annotations

from pathlib import Path

import pytest

from armplan.demo import DEFAULT_TASK
from armplan.demo.outputs import Execution, export_frames, write_outputs
from armplan.demo.task import load_task
from bridge.minimum_jerk import minimum_jerk_trajectory
from bridge.naoqi_client import NaoqiClient
from bridge.robot_bridge import RobotBridge
from bridge.sim import SimProcess
from shared.errors import InvalidInputError
from shared.robot.postures import forward, rest

NAMES = ("trajectory.json", "behavior.xar", "play.py", "report.json")


@pytest.fixture
def run(sim: SimProcess) -> Execution:
    """A 1 s reach played on the sim, as the demo's run."""
    trajectory = minimum_jerk_trajectory(
        "right", [rest("right"), forward("right")], [1.0]
    )
    robot = RobotBridge(NaoqiClient(sim.url))
    try:
        reply = robot.execute(trajectory)
    finally:
        robot.client.close()
    frames = export_frames(trajectory, 25.0)
    return Execution(
        load_task(DEFAULT_TASK), trajectory, reply, sim.url, True, 25.0, frames
    )


@pytest.mark.parametrize("blocked", NAMES)
def test_one_output_that_cannot_be_written_leaves_none(
    tmp_path: Path, run: Execution, blocked: str
) -> None:
    """A folder where one output's partial goes: none of the four is
    written, the error names that output (not its partial name)."""
    out = tmp_path / "out"
    (out / f"{blocked}.partial").mkdir(parents=True)
    with pytest.raises(InvalidInputError) as caught:
        write_outputs(out, run)
    assert caught.value.message.startswith(f"cannot write {out / blocked}: ")
    assert sorted(p.name for p in out.iterdir()) == [f"{blocked}.partial"]


def test_the_outputs_are_written_whole(tmp_path: Path, run: Execution) -> None:
    """All four, no partial left."""
    out = tmp_path / "out"
    out.mkdir()
    files = write_outputs(out, run)
    assert sorted(p.name for p in files.values()) == sorted(NAMES)
    assert sorted(p.name for p in out.iterdir()) == sorted(NAMES)
    assert '"frames"' in (out / "report.json").read_text()
