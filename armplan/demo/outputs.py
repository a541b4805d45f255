"""What ``armplan demo`` writes into its folder.

- ``trajectory.json``: the planned trajectory in the SPEC's form (``arm``,
  ``joint_names``, ``times`` [s], ``positions`` [rad], ``velocities``,
  ``accelerations``, ``primitives``);
- ``behavior.xar``: the trajectory as a Choregraphe behavior (a script box
  moving the arm to the start slowly, then a timeline of keys per actuator,
  degrees, 25 fps; ``bridge.choregraphe``);
- ``play.py``: Choregraphe's "export to Python" form of the same frames,
  runnable against a NAO (``python play.py tcp://IP:9559``);
- ``report.json``: the tracking report (``tracking_rms_deg``,
  ``tracking_max_deg`` keyed by joint name, latency, samples) with what was
  executed where and the task's phases.

The recording (``session.mcap``), the simulated NAO's log (``sim.jsonl``) and
the processes' logs (``logs/``) are written by the processes themselves.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any, NamedTuple

from armplan.demo.task import Task
from bridge import FrameLimits, checked_frames, write_behavior, write_python
from shared.messages import ExecuteReply, Trajectory

TRAJECTORY_FILE = "trajectory.json"
BEHAVIOR_FILE = "behavior.xar"
PYTHON_FILE = "play.py"
REPORT_FILE = "report.json"


class Execution(NamedTuple):
    """One run of the task.

    Attributes:
        task: The task.
        trajectory: The planned trajectory.
        reply: The bridge's answer (tracking report, executed states).
        robot: The robot's NAOqi address.
        simulated: True if the robot was the simulated NAO.
        rate: Frame rate of the command frames [Hz].
    """

    task: Task
    trajectory: Trajectory
    reply: ExecuteReply
    robot: str
    simulated: bool
    rate: float


def write_outputs(out: Path, run: Execution) -> dict[str, Path]:
    """Write the trajectory, its exports and the report; returns them by name."""
    limits = FrameLimits.for_arm(run.trajectory.arm)
    frames = checked_frames(run.trajectory, run.rate, limits, behavior=True)
    files = {
        "trajectory": out / TRAJECTORY_FILE,
        "choregraphe": write_behavior(frames, out / BEHAVIOR_FILE),
        "python": write_python(frames, out / PYTHON_FILE),
        "report": out / REPORT_FILE,
    }
    files["trajectory"].write_text(run.trajectory.to_json() + "\n", encoding="utf-8")
    report = report_document(run)
    files["report"].write_text(json.dumps(report, indent=2) + "\n", encoding="utf-8")
    return files


def report_document(run: Execution) -> dict[str, Any]:
    """``report.json``: the tracking report first, then the context."""
    report = run.reply.report.model_dump(mode="json")
    trajectory = run.trajectory
    return {
        **report,
        "robot": run.robot,
        "simulated": run.simulated,
        "frames": run.reply.frames,
        "frame_rate": run.rate,
        "approach_duration": run.reply.approach_duration,
        "trajectory": {
            "arm": trajectory.arm.value,
            "duration": trajectory.duration,
            "samples": len(trajectory.times),
            "primitives": _in_order(trajectory.primitives),
        },
        "task": {
            "name": run.task.name,
            "start": list(run.task.start),
            "phases": [
                {
                    "name": phase.name,
                    "says": phase.says,
                    "targets": [t.model_dump(mode="json") for t in phase.targets],
                }
                for phase in run.task.phases
            ],
        },
    }


def _in_order(labels: list[str]) -> list[str]:
    """The distinct labels in order of first appearance."""
    return list(dict.fromkeys(labels))
