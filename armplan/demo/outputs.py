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
from bridge import (
    FrameLimits,
    behavior_xml,
    checked_frames,
    frame_velocities,
    python_script,
)
from shared.messages import CommandFrames, ExecuteReply, Trajectory
from shared.output_paths import replaced_together

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
        frames: The frames the exports hold (:func:`export_frames`).
    """

    task: Task
    trajectory: Trajectory
    reply: ExecuteReply
    robot: str
    simulated: bool
    rate: float
    frames: CommandFrames


def export_frames(trajectory: Trajectory, rate: float) -> CommandFrames:
    """The frames of ``behavior.xar`` and ``play.py``, checked for both.

    Checked before the robot moves: the behavior's curve (the keys and
    their tangents, ``bridge.bezier_curve``) could break a limit the
    bridge's frames keep, and a demo refused after it played would say
    nothing was sent.

    Raises:
        InvalidInputError: a frame or the behavior's curve breaks a limit,
            with a frame rate that passes if there is one.
    """
    limits = FrameLimits.for_arm(trajectory.arm)
    return checked_frames(trajectory, rate, limits, behavior=True)


def write_outputs(out: Path, run: Execution) -> dict[str, Path]:
    """Write the trajectory, its exports and the report; returns them by name.

    They are written as a set (``replaced_together``): a SIGTERM or a failed
    write in the middle leaves none of them, not a ``behavior.xar`` without
    the trajectory and report it came with.

    Raises:
        InvalidInputError: a file cannot be written (a full disk), naming
            it and the operating system's reason.
    """
    files = {
        "trajectory": out / TRAJECTORY_FILE,
        "choregraphe": out / BEHAVIOR_FILE,
        "python": out / PYTHON_FILE,
        "report": out / REPORT_FILE,
    }
    velocities = frame_velocities(run.trajectory, run.frames)
    texts = [  # in the order of ``files``
        run.trajectory.to_json() + "\n",
        behavior_xml(run.frames, velocities=velocities),
        python_script(run.frames),
        json.dumps(report_document(run), indent=2) + "\n",
    ]
    with replaced_together(list(files.values())) as partials:
        for partial, text in zip(partials, texts, strict=True):
            partials.write_text(partial, text)  # a failed write names the file
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
            "palm_reached": [
                None if palm is None else palm.model_dump(mode="json")
                for palm in trajectory.palm_reached or []
            ],
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
