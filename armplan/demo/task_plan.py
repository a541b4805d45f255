"""The demo's task planned here, before anything starts.

The distance band (:func:`services.ik.check_reachable`) passes targets the
IK cannot reach (0.146 m behind the shoulder; a palm it cannot turn to) and
says nothing of a trajectory too long to send: the demo started its nine
processes, removed the folder's earlier results and failed about 8 s later
naming neither the file nor the phase. :func:`check_task_plans` runs the
planner's own pipeline (:func:`services.planner.pipeline.plan`, its stages
in this process: the code the services run) on the task's request. A
movement it cannot make is named by file, phase and target number (found,
only then, by planning the task up to each target in turn). It adds about
0.5 s to the demo's start (the shipped task, 2 CPUs: 0.4 s importing the
planner, 0.1 s planning).
"""

from __future__ import annotations

from pathlib import Path

from armplan.demo.task import FORM, Task
from shared.errors import (
    ArmplanError,
    InvalidInputError,
    PrimitiveCannotReachError,
    UnreachableTargetError,
)

#: What a too-long task can do in the demo: ``armplan demo`` sets no rate
#: (only ``DemoOptions.rate`` does, from Python, and only the frames').
DEMO_ADVICE = "shorten the dwells or split the task into several task files"
#: The planner's advice for a too-long request, which names a rate.
RATE_ADVICE = ("lower the rate or split the task", "split the task or lower the rate")
#: Failures of one movement, named by its phase and target.
MOVEMENT_ERRORS = (UnreachableTargetError, PrimitiveCannotReachError)


def check_task_plans(task: Task, path: Path) -> None:
    """Raise, naming ``path``, if the planner refuses ``task``.

    Raises:
        InvalidInputError: naming the file, and for a movement the planner
            cannot make its phase and target number (1-based, in the phase).
    """
    from services.planner.pipeline import plan  # 0.4 s of imports

    try:
        plan(task.plan_request())
    except MOVEMENT_ERRORS as error:
        raise _named(path, f"{_failing_target(task)}: {error.message}") from None
    except ArmplanError as error:
        raise _named(path, demo_advice(error.message)) from None


def _failing_target(task: Task) -> str:
    """The phase and target of the first movement the planner cannot make."""
    from services.planner.pipeline import plan

    labels = [
        (phase.name, number)
        for phase in task.phases
        for number in range(1, len(phase.targets) + 1)
    ]
    request = task.plan_request()
    for count, (name, number) in enumerate(labels, 1):
        part = request.model_copy(update={"targets": request.targets[:count]})
        try:
            plan(part)
        except MOVEMENT_ERRORS:
            return f"phase {name!r}, target {number}"
        except ArmplanError:
            continue  # e.g. too long already: its movements were made
    return "a movement of the task"


def demo_advice(message: str) -> str:
    """``message`` with its advice to lower the rate replaced by the demo's."""
    for advice in RATE_ADVICE:
        if message.endswith(advice):
            return message.removesuffix(advice) + DEMO_ADVICE
    return message


def _named(path: Path, message: str) -> InvalidInputError:
    """The error for the task file ``path``, worded as ``load_task``'s."""
    return InvalidInputError(f"{path}: {message} ({FORM})", field="task")
