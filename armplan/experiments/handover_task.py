"""The handover task as data: ``handover_task.json`` beside this module.

The file (its ``about`` field says the same) lists the task's movements in
the person's terms: each a wrist target in the person's shoulder frame as a
fraction of the arm length, and whether its palm direction counts (a grasp
or a release). ``load_task`` reads and validates it; any other file of the
same form can be given instead.
"""

from __future__ import annotations

import json
from importlib import resources
from pathlib import Path
from typing import NamedTuple

import numpy as np

from shared.errors import InvalidInputError

#: The shipped task, inside this package.
TASK_FILE = "handover_task.json"
#: Start postures a task can name (functions of ``shared.robot.postures``).
STARTS = ("forward", "rest")
#: Shoulder-to-target distances a person's arm can take, as fractions of L [-].
REACH = (0.3, 1.0)


class Movement(NamedTuple):
    """One movement of the task.

    Attributes:
        name: What it does, e.g. ``"take red block"``.
        target: Wrist target, shoulder frame, in arm lengths [-], shape (3,).
        palm: Whether the palm direction at the end counts.
    """

    name: str
    target: np.ndarray
    palm: bool


class Task(NamedTuple):
    """The task: the start posture and the movements in order.

    Attributes:
        start: Name of NAO's start posture, one of ``STARTS``.
        movements: The movements.
    """

    start: str
    movements: list[Movement]


def default_task_path() -> Path:
    """Where the shipped task file lives."""
    return Path(str(resources.files("armplan.experiments").joinpath(TASK_FILE)))


def load_task(path: str | Path | None = None) -> Task:
    """The task in ``path`` (default: the shipped one).

    Raises:
        InvalidInputError: naming the file and what is wrong with it.
    """
    path = Path(path) if path is not None else default_task_path()
    try:
        data = json.loads(path.read_text())
        task = Task(str(data["start"]), [_movement(m) for m in data["movements"]])
    except (OSError, ValueError, KeyError, TypeError) as exc:
        raise InvalidInputError(
            f"task file {path}: {type(exc).__name__}: {exc}", field="task"
        ) from None
    _check(task, path)
    return task


def _vector(values: object) -> np.ndarray:
    out = np.array(values, dtype=float)
    if out.shape != (3,) or not np.all(np.isfinite(out)):
        raise ValueError(f"expected 3 finite numbers, got {values!r}")
    return out


def _movement(item: dict[str, object]) -> Movement:
    return Movement(str(item["name"]), _vector(item["target"]), bool(item["palm"]))


def _check(task: Task, path: Path) -> None:
    if task.start not in STARTS:
        raise InvalidInputError(
            f"task file {path}: unknown start posture {task.start!r}; "
            f"known: {', '.join(STARTS)}",
            field="task",
        )
    if not task.movements:
        raise InvalidInputError(f"task file {path}: no movements", field="task")
    for move in task.movements:
        reach = float(np.linalg.norm(move.target))
        if not REACH[0] <= reach <= REACH[1]:
            raise InvalidInputError(
                f"task file {path}: target of {move.name!r} is {reach:.3f} arm "
                f"lengths from the shoulder; a person reaches {REACH[0]}-{REACH[1]}",
                field="task",
            )
