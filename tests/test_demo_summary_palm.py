"""The demo's summary and report.json say the palm wanted and reached at each target.

A task with three palm directions printed none of them, though the palm
ended 49.9 degrees from one (``armplan plan`` and ``ik`` print it). Real
parts: the task planned by the planner's pipeline, played on the simulated
NAO over libqi.
"""

from __future__ import annotations

import json
from pathlib import Path

from armplan.demo.outputs import Execution, export_frames, report_document
from armplan.demo.summary import task_lines
from armplan.demo.task import load_task
from bridge.naoqi_client import NaoqiClient
from bridge.robot_bridge import RobotBridge
from bridge.sim import SimProcess
from services.planner.pipeline import plan

PALMS = [
    ("palm down", [0.14, -0.10, 0.06], [0, 0, -1]),
    ("hold", [0.13, -0.12, 0.07], None),
    ("palm left", [0.12, -0.10, 0.08], [0, 1, 0]),
]


def test_the_summary_says_each_palm_wanted_and_reached(
    tmp_path: Path, sim: SimProcess
) -> None:
    phases = []
    for name, position, palm in PALMS:
        target: dict = {"position": position, "dwell": 0.2}
        if palm is not None:
            target["palm"] = palm
        phases.append({"name": name, "targets": [target]})
    path = tmp_path / "palm.json"
    path.write_text(json.dumps({"start": "forward", "phases": phases}))
    task = load_task(path)
    trajectory = plan(task.plan_request()).trajectory
    robot = RobotBridge(NaoqiClient(sim.url))
    try:
        reply = robot.execute(trajectory)
    finally:
        robot.client.close()
    frames = export_frames(trajectory, 25.0)
    run = Execution(task, trajectory, reply, sim.url, True, 25.0, frames)
    lines = task_lines(run)
    palms = [line.strip() for line in lines if "palm at target" in line]
    assert trajectory.palm_reached is not None
    reached = [r for r in trajectory.palm_reached if r is not None]
    assert len(palms) == len(reached) == 2
    for line, palm in zip(palms, reached, strict=True):
        assert line.startswith(f"palm at target 1 {palm.angle_deg:.1f} deg from")
    assert "(0.000, 0.000, -1.000)" in palms[0]
    assert "(0.000, 1.000, 0.000)" in palms[1]
    below = lines.index(next(line for line in lines if "palm left" in line)) + 1
    assert "(0.000, 1.000, 0.000)" in lines[below]
    document = json.loads(json.dumps(report_document(run)))
    saved = document["trajectory"]["palm_reached"]
    assert [p is None for p in saved] == [p is None for p in trajectory.palm_reached]
    for palm, kept in zip(trajectory.palm_reached, saved, strict=True):
        if palm is not None:
            assert kept["angle_deg"] == palm.angle_deg
            assert kept["wanted"] == list(palm.wanted)
