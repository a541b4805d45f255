"""The demo plans its task before anything starts (``armplan.demo.task_plan``).

A target the distance band passes but the IK cannot reach (behind the
shoulder, a side target 0.116 m from it, a palm it cannot turn to) started
every process, removed the folder's earlier results and failed about 8 s
later naming neither the file nor the phase; a task too long to send was
told to lower a rate ``armplan demo`` has no option for.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from armplan.demo import DEFAULT_TASK, DemoOptions, load_task, run_demo
from armplan.demo.earlier_run import LIST_FILE
from armplan.demo.task_plan import check_task_plans
from armplan.launch import free_endpoint
from shared.bus import load_config
from shared.errors import InvalidInputError


def task_file(tmp_path: Path, task: dict[str, Any]) -> Path:
    """``task`` written as a task file."""
    path = tmp_path / "task.json"
    path.write_text(json.dumps(task))
    return path


def one_target(position: list[float], palm: list[float] | None = None) -> dict:
    """A task of one phase, ``"reach"``, with a target after a first one."""
    first = {"position": [0.14, -0.10, 0.06], "dwell": 0.2}
    target: dict[str, Any] = {"position": position, "dwell": 0.2}
    if palm is not None:
        target["palm"] = palm
    return {"phases": [{"name": "reach", "targets": [first, target]}]}


@pytest.mark.parametrize(
    ("task", "words"),
    [
        (one_target([-0.14, -0.10, 0.06]), r"the IK solver stopped 46\.4 mm"),
        (one_target([0.0333, -0.2091, 0.1]), r"0\.1160 m from the right shoulder"),
    ],
)
def test_a_target_the_ik_misses_is_refused_before_anything_starts(
    tmp_path: Path, task: dict[str, Any], words: str
) -> None:
    """Within the distance band but out of the IK's reach: refused naming
    the file, the phase and the target, before any process starts and with
    the earlier run's results left in the folder."""
    path = task_file(tmp_path, task)
    out = tmp_path / "results"
    out.mkdir()
    (out / LIST_FILE).write_text("report.json\n")
    (out / "report.json").write_text("{}")
    config = load_config(None).with_endpoints((free_endpoint(),), "--listen")
    said: list[str] = []
    with pytest.raises(
        InvalidInputError, match=rf"^{path}: phase 'reach', target 2: .*{words}"
    ):
        run_demo(DemoOptions(config, out=out, task=path), said.append)
    assert said == []
    assert (out / "report.json").read_text() == "{}"


def test_a_palm_the_ik_cannot_turn_to_is_refused_naming_the_phase(
    tmp_path: Path,
) -> None:
    """The shipped task with the palm (1, 0, 0) at its first target: the
    palm's roll is named, with the WristYaw it needs."""
    task = json.loads(DEFAULT_TASK.read_text())
    task["phases"][0]["targets"][0]["palm"] = [1, 0, 0]
    path = task_file(tmp_path, task)
    name = task["phases"][0]["name"]
    with pytest.raises(
        InvalidInputError,
        match=rf"^{path}: phase '{name}', target 1: .*the palm cannot be turned "
        r"towards \(1, 0, 0\) there: .* needs WristYaw",
    ):
        check_task_plans(load_task(path), path)


def test_a_task_too_long_is_told_what_the_demo_can_change(tmp_path: Path) -> None:
    """Ten dwells of 59.9 s and the reaches between them make over 60000
    samples at the demo's 100 Hz: refused naming the file, without advice
    to lower a rate."""
    centre = np.array([0.13, -0.12, 0.08])
    turns = np.linspace(0.0, 2.0 * np.pi, 10, endpoint=False)
    targets = [
        {
            "position": list(centre + 0.03 * np.array([0, np.cos(a), np.sin(a)])),
            "dwell": 59.9,
        }
        for a in turns
    ]
    path = task_file(tmp_path, {"phases": [{"name": "wait", "targets": targets}]})
    with pytest.raises(InvalidInputError) as caught:
        check_task_plans(load_task(path), path)
    message = caught.value.message
    assert message.startswith(f"{path}: the trajectory would have")
    assert "shorten the dwells or split the task" in message
    assert "rate or" not in message and "lower the rate" not in message


def test_the_shipped_task_plans() -> None:
    check_task_plans(load_task(), DEFAULT_TASK)
