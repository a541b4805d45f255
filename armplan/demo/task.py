"""The demo's task: the paper's human-robot collaboration, as wrist targets.

The task file (``handover_task.json`` beside this module, or any file of the
same form) names the arm, the start posture and the phases; each phase is a
list of wrist targets (``shared.messages.ReachTarget``: torso frame [m], an
optional palm direction, a dwell [s]). :func:`plan_request` makes the one
``PlanRequest`` that moves through every target in order, so the planner
returns one trajectory for the whole task. Targets are the wrist's (the
WristYaw origin); NAO's wrist reaches 0.114-0.162 m from its shoulder.
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from shared.errors import InvalidInputError, UnreachableTargetError
from shared.messages import PlanRequest, ReachTarget, parse
from shared.robot import Side, load_arm
from shared.robot.postures import forward, rest

#: The shipped task: the paper's handover experiment.
DEFAULT_TASK = Path(__file__).with_name("handover_task.json")
#: Named start postures a task file may use instead of five angles.
POSTURES = {"forward": forward, "rest": rest}


@dataclass(frozen=True)
class Phase:
    """One step of the task.

    Attributes:
        name: Short name, e.g. ``"take the red block"``.
        says: What NAO does, in words.
        targets: Its wrist targets, in order.
    """

    name: str
    says: str
    targets: tuple[ReachTarget, ...]


@dataclass(frozen=True)
class Task:
    """A whole demo task.

    Attributes:
        name: The task's name.
        arm: The arm that moves.
        start: Start posture [rad], shape (5,).
        phases: The steps, in order.
    """

    name: str
    arm: Side
    start: tuple[float, ...]
    phases: tuple[Phase, ...]

    def targets(self) -> list[ReachTarget]:
        """Every phase's targets, in order."""
        return [target for phase in self.phases for target in phase.targets]

    def plan_request(self) -> PlanRequest:
        """The one request that moves through every target (human pace, mp).

        Raises:
            InvalidInputError: naming the field (e.g. a start of four angles).
        """
        targets = [t.model_dump() for t in self.targets()]
        request = {"arm": self.arm.value, "targets": targets, "start": self.start}
        return parse(PlanRequest, request)


def load_task(path: str | Path = DEFAULT_TASK) -> Task:
    """Read a task file.

    Raises:
        InvalidInputError: naming the file and what is wrong in it.
    """
    data = _read_json(Path(path))
    try:
        arm = Side.parse(data.get("arm", "right"))
        phases = tuple(_phase(p) for p in data["phases"])
        start = _start(data.get("start", "forward"), arm)
        task = Task(str(data.get("name", Path(path).stem)), arm, start, phases)
        task.plan_request()  # checks the whole request once, here
        _check_reach(task)
        return task
    except InvalidInputError as error:
        raise InvalidInputError(f"{path}: {error.message}", field="task") from None
    except (KeyError, TypeError, AttributeError) as error:
        raise InvalidInputError(
            f"{path}: not a task file ({type(error).__name__}: {error}); see "
            f"{DEFAULT_TASK.name} for the form",
            field="task",
        ) from None


def _check_reach(task: Task) -> None:
    """Raise, naming the phase, if a target is out of the arm's reach."""
    from services.ik import check_reachable  # the IK stage's own check

    arm = load_arm(task.arm)
    for phase in task.phases:
        for target in phase.targets:
            try:
                check_reachable(arm, np.array(target.position))
            except UnreachableTargetError as error:
                raise InvalidInputError(
                    f"phase {phase.name!r}: {error.message}", field="targets"
                ) from None


def _read_json(path: Path) -> dict[str, Any]:
    try:
        data = json.loads(path.read_text(encoding="utf-8"))
    except OSError as error:
        raise InvalidInputError(
            f"cannot read task file {path}: {error.strerror}", field="task"
        ) from None
    except ValueError as error:
        raise InvalidInputError(f"{path} is not JSON: {error}", field="task") from None
    if not isinstance(data, dict) or not data.get("phases"):
        raise InvalidInputError(f"{path}: a task needs a list of phases", field="task")
    return data


def _phase(data: dict[str, Any]) -> Phase:
    targets = tuple(parse(ReachTarget, t) for t in data["targets"])
    if not targets:
        raise InvalidInputError(f"phase {data['name']!r} has no targets", field="task")
    return Phase(str(data["name"]), str(data.get("says", "")), targets)


def _start(value: str | list[float], arm: Side) -> tuple[float, ...]:
    if isinstance(value, str):
        if value not in POSTURES:
            raise InvalidInputError(
                f"unknown start posture {value!r}; known: {', '.join(POSTURES)} "
                "or five joint angles [rad]",
                field="start",
            )
        return tuple(float(q) for q in POSTURES[value](arm))
    return tuple(float(q) for q in value)
