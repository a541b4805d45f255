"""The demo's task: the paper's human-robot collaboration, as wrist targets.

The task file (``handover_task.json`` beside this module, or any file of the
same form) names the arm, the start posture and the phases; each phase is a
list of wrist targets (``shared.messages.ReachTarget``: torso frame [m], an
optional palm direction, a dwell [s], an optional hand action, ``"open"`` or
``"close"``, done during the dwell). :func:`plan_request` makes the one
``PlanRequest`` that moves through every target in order, so the planner
returns one trajectory for the whole task. Targets are the wrist's (the
WristYaw origin); NAO's wrist reaches 0.114-0.162 m from its shoulder.
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from pydantic import Field, field_validator

from shared.errors import InvalidInputError, JointLimitError, UnreachableTargetError
from shared.input_files import read_at_most, without_byte_order_mark
from shared.messages import PlanRequest, ReachTarget, parse
from shared.messages.base import Message
from shared.messages.repeated_keys import check_keys_once
from shared.robot import Side, load_arm
from shared.robot.postures import forward, rest
from shared.robot.side import SideAnyCase

#: The shipped task: the paper's handover experiment.
DEFAULT_TASK = Path(__file__).with_name("handover_task.json")
#: The error's pointer to the form a task file takes: the shipped task's
#: real path (in the installed package too), not its name alone.
FORM = f"see {DEFAULT_TASK} for the form"
#: A PlanRequest's keys a demo task has none of (``armplan plan --task``'s
#: form): a file holding one and no ``phases`` is a PlanRequest.
PLAN_REQUEST_KEYS = frozenset(PlanRequest.model_fields) - {"arm", "start"}
#: Named start postures a task file may use instead of five angles.
POSTURES = {"forward": forward, "rest": rest}
#: Joint angles in a start posture given as numbers.
ANGLES = 5


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


class TaskPhase(Message):
    """A phase as the task file writes it.

    Attributes:
        name: Short name.
        says: What NAO does, in words.
        targets: Its wrist targets, in order, at least one.
    """

    name: str = Field(min_length=1)
    says: str = ""
    targets: list[ReachTarget] = Field(min_length=1)


class TaskFile(Message):
    """The task file's form (see ``handover_task.json``); unknown keys are refused.

    Attributes:
        name: The task's name (default: the file's name).
        source: Where the task comes from, in words.
        arm: The arm that moves.
        frame: The targets' frame, in words.
        start: ``"forward"``, ``"rest"`` or five joint angles [rad], within
            the joints' ranges.
        start_note: Why this start, in words.
        phases: The steps, in order, at least one.
    """

    name: str | None = None
    source: str = ""
    arm: SideAnyCase = Side.RIGHT
    frame: str = ""
    start: str | list[float] = "forward"
    start_note: str = ""
    phases: list[TaskPhase] = Field(min_length=1)

    @field_validator("start", mode="before")
    @classmethod
    def _start(cls, value: object) -> object:
        """A named posture or five numbers, said in one message if neither."""
        if isinstance(value, str) and value in POSTURES:
            return value
        if (
            isinstance(value, list)
            and len(value) == ANGLES
            and all(_finite_number(q) for q in value)
        ):
            return value
        raise ValueError(
            f"the start posture must be {' or '.join(map(repr, POSTURES))}, or "
            f"{ANGLES} joint angles [rad] as finite numbers"
        )


def _finite_number(value: object) -> bool:
    """Whether ``value`` is a finite int or float (not a bool)."""
    return (
        isinstance(value, int | float)
        and not isinstance(value, bool)
        and math.isfinite(value)
    )


def load_task(path: str | Path = DEFAULT_TASK) -> Task:
    """Read a task file.

    Raises:
        InvalidInputError: naming the file and what is wrong in it.
    """
    path = Path(path)
    text = b""
    try:
        text = _read(path)
        check_keys_once(text, TaskFile.__name__)
        data = parse(TaskFile, text)
        start = data.start
        angles = POSTURES[start](data.arm) if isinstance(start, str) else start
        phases = tuple(
            Phase(phase.name, phase.says, tuple(phase.targets)) for phase in data.phases
        )
        name = data.name or path.stem
        task = Task(name, data.arm, tuple(float(q) for q in angles), phases)
        task.plan_request()  # checks the whole request once, here
        load_arm(task.arm).limits.check(np.array(task.start), "in the start posture")
        _check_reach(task)
        return task
    except (InvalidInputError, JointLimitError) as error:
        raise InvalidInputError(
            f"{path}: {error.message} ({_plan_request_hint(text)}{FORM})",
            field="task",
        ) from None


def _plan_request_hint(text: bytes) -> str:
    """A pointer to ``armplan plan --task`` when the file is a PlanRequest.

    ``plan --task`` takes one ``PlanRequest`` (``targets`` or a
    ``wrist_path``, ...); a demo task holds ``phases`` of targets. Given to
    ``demo --task``, a PlanRequest read "phases: Field required" alone.
    """
    try:
        fields = json.loads(text)
    except (ValueError, RecursionError):  # read as "not valid JSON" already
        return ""
    if not isinstance(fields, dict) or "phases" in fields:
        return ""
    if not PLAN_REQUEST_KEYS & set(fields):
        return ""
    return (
        "this file is a PlanRequest, for `armplan plan --task FILE`; "
        "`demo --task` takes a demo task of phases: "
    )


def _check_reach(task: Task) -> None:
    """Raise, naming the phase, if a target is out of the arm's reach."""
    from services.ik import check_target  # the IK stage's own check

    arm = load_arm(task.arm)
    for phase in task.phases:
        for target in phase.targets:
            try:
                check_target(arm, np.array(target.position))
            except UnreachableTargetError as error:
                raise InvalidInputError(
                    f"phase {phase.name!r}: {error.message}", field="targets"
                ) from None


def _read(path: Path) -> bytes:
    """The file's bytes; InvalidInputError naming it if it cannot be read."""
    try:
        return without_byte_order_mark(read_at_most(path))
    except OSError as error:
        raise InvalidInputError(
            f"cannot read task file {path}: {error.strerror}", field="task"
        ) from None
