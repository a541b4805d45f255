"""The ``PlanRequest`` an ``armplan plan`` command line asks for.

Three ways to say what to do, one per command line:

- ``--target X Y Z``, once per target, reached in order. ``--dwell S``,
  ``--palm X Y Z`` and ``--hand open|close`` belong to the ``--target``
  they follow: hold S seconds there [s], face the palm that way there
  (torso frame), open or close the hand during the hold. So "reach, hold
  half a second, retreat" is
  ``--target 0.12 -0.10 0.05 --dwell 0.5 --target 0.10 -0.14 0.0``, and
  "reach, grasp, retreat" ``--target 0.12 -0.10 0.05 --hand close --target
  0.10 -0.14 0.0``.
- ``--wrist-path FILE.csv``: a timed wrist path (header ``t,x,y,z``, s and
  m); ``--palm`` (once) is the palm direction held along it. Its times are
  kept, so ``--fastest``, ``--rate`` and ``--dwell`` do not apply (nor
  do they, or a task's ``fastest`` and ``rate``, to a task's wrist path).
- ``--task FILE.json``: a whole ``PlanRequest`` as JSON, the message the
  planner service takes. ``--method``, ``--fastest``, ``--rate``,
  ``--start``, the weights and the limits given beside it override the
  file's; ``--arm`` must agree with the file's arm (or its wrist path's),
  or gives it where the file names none; ``--dwell``, ``--palm`` and
  ``--hand`` belong in the file.
"""

from __future__ import annotations

import argparse
import json
import math
import re
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from armplan.cli.parsing import measure_fields
from shared.errors import InvalidInputError
from shared.input_files import (
    MAX_INPUT_BYTES,
    read_at_most,
    without_byte_order_mark,
)
from shared.messages import PlanRequest, WristPath, parse
from shared.messages.repeated_keys import check_keys_once
from shared.robot.side import Side

#: Largest task file read [bytes] (the services' default payload limit).
MAX_TASK_BYTES = MAX_INPUT_BYTES
#: Options that belong to the ``--target`` before them.
PER_TARGET = ("--dwell", "--palm", "--hand")

Step = tuple[str, Any]


class StepAction(argparse.Action):
    """Records ``--target``, ``--dwell``, ``--palm``, ``--hand`` in command-line order.

    Each occurrence appends ``(option, values)`` to ``namespace.<dest>``, so
    the request builder can tell which target a ``--dwell`` follows.
    """

    def __call__(
        self,
        parser: argparse.ArgumentParser,
        namespace: argparse.Namespace,
        values: Any,
        option_string: str | None = None,
    ) -> None:
        steps = list(getattr(namespace, self.dest) or [])
        steps.append((self.option_strings[0], values))
        setattr(namespace, self.dest, steps)


def request_from_args(args: argparse.Namespace) -> PlanRequest:
    """The validated request the options describe.

    Raises:
        InvalidInputError: naming the option, target, file, line or field
            that is wrong.
    """
    if args.task:
        return _from_task(args)
    if args.wrist_path:
        return _from_wrist_path(args)
    targets = targets_from_steps(args.steps)
    fields = _how(args) | {"arm": _side(args), "targets": targets}
    try:
        return parse(PlanRequest, fields)
    except InvalidInputError as exc:
        raise _per_target(exc) from None


def targets_from_steps(steps: Sequence[Step] | None) -> list[dict[str, Any]]:
    """``ReachTarget`` fields per ``--target``, with the options that follow it.

    Raises:
        InvalidInputError: a ``--dwell``/``--palm``/``--hand`` before any
            target, given twice for one target, or a value that is not a
            finite number.
    """
    targets: list[dict[str, Any]] = []
    for option, values in steps or []:
        if option == "--target":
            name = f"--target number {len(targets) + 1}"
            targets.append({"position": _finite(values, name)})
            continue
        if not targets:
            raise InvalidInputError(
                f"{option} comes before any --target: write it after the "
                "target it belongs to",
                field=option[2:],
            )
        key, number = option[2:], len(targets)
        if key in targets[-1]:
            raise InvalidInputError(
                f"--target number {number} has {option} twice", field=key
            )
        targets[-1][key] = (
            values
            if isinstance(values, str)
            else _finite(values, f"{option} of --target number {number}")
        )
    return targets


def _per_target(error: InvalidInputError) -> InvalidInputError:
    """``error`` on a target's field, told in command-line terms."""
    match = re.fullmatch(r"targets\.(\d+)\.(\w+)(\..*)?", error.field)
    if match is None:
        return error
    key = match[2]
    option = "--target" if key == "position" else f"--{key} of --target"
    return InvalidInputError(
        f"{option} number {int(match[1]) + 1}: {error.message}", field=error.field
    )


def _side(args: argparse.Namespace) -> Side:
    """The arm asked for (default: right)."""
    return Side.parse(args.arm or Side.RIGHT)


def _how(args: argparse.Namespace) -> dict[str, Any]:
    """The options given that say how to plan: method, pace, rate, start, weights."""
    fields: dict[str, Any] = {}
    if args.method is not None:
        fields["method"] = args.method
    if args.fastest:
        fields["fastest"] = True
    if args.rate is not None:
        fields["rate"] = _finite(args.rate, "--rate")
    if args.start is not None:
        fields["start"] = _finite(args.start, "--start")
    other = getattr(args, "other_arm", None)
    if other is not None:
        fields["other_arm"] = _finite(other, "--other-arm")
    tolerance = getattr(args, "path_tolerance", None)
    if tolerance is not None:
        fields["path_tolerance"] = _finite(tolerance, "--path-tolerance")
    for name, value in measure_fields(args).items():
        fields.setdefault("measures", {})[name] = _finite(value, f"--{name}")
    for name in ("acceleration", "jerk"):
        values = getattr(args, f"max_{name}", None)
        if values is not None:
            fields.setdefault("limits", {})[name] = _limit(values, name)
    return fields


def _limit(values: list[float], name: str) -> float | list[float]:
    """``--max-<name>``'s values: one for every joint, or five."""
    option = f"--max-{name}"
    if len(values) not in (1, 5):
        raise InvalidInputError(
            f"{option} takes one value (every joint) or five (ShoulderPitch to "
            f"WristYaw), got {len(values)}",
            field=name,
        )
    _finite(values, option)
    if min(values) <= 0.0:
        raise InvalidInputError(
            f"{option} must be positive, got {min(values):g}", field=name
        )
    return values[0] if len(values) == 1 else values


def _from_wrist_path(args: argparse.Namespace) -> PlanRequest:
    """Follow the CSV's wrist path at its own times."""
    from services.decide.wrist_csv import read_wrist_csv

    for given, option in ((args.fastest, "--fastest"), (args.rate, "--rate")):
        if given:
            raise _kept_times(option)
    palms = [values for option, values in args.steps or [] if option == "--palm"]
    for option, _ in args.steps or []:
        if option == "--hand":
            raise InvalidInputError(
                "--hand belongs to a --target and --wrist-path has none: the "
                "hand acts during a target's dwell",
                field="hand",
            )
    if len(palms) < len(args.steps or []):
        raise InvalidInputError(
            "--dwell belongs to a --target and --wrist-path has none: hold still "
            "in the path itself (the same position at later times)",
            field="dwell",
        )
    if len(palms) > 1:
        raise InvalidInputError("--palm given twice for one wrist path", field="palm")
    path = read_wrist_csv(args.wrist_path, _side(args))
    if palms:
        fields = path.model_dump() | {"palm": _finite(palms[0], "--palm")}
        path = parse(WristPath, fields)
    return parse(PlanRequest, _how(args) | {"arm": path.arm, "wrist_path": path})


def _kept_times(option: str, path: str = "--wrist-path") -> InvalidInputError:
    return InvalidInputError(
        f"{option} does not apply to {path}: the path's own times are kept "
        "(no retiming)",
        field=option.removeprefix("--"),
    )


def _no_retiming(args: argparse.Namespace, request: PlanRequest, path: Path) -> None:
    """Refuse a pace or rate, beside a task or in it, for its wrist path.

    They were ignored: ``--task`` with a 50 Hz path and ``--rate 10`` gave
    the path's 50 Hz samples.
    """
    if request.wrist_path is None:
        return
    for given, option in ((args.fastest, "--fastest"), (args.rate, "--rate")):
        if given:
            raise _kept_times(option, f"the wrist_path of the task {path}")
    for name in ("fastest", "rate"):
        if name in request.model_fields_set:
            raise _kept_times(name, f"a wrist_path (the task {path})")


def _from_task(args: argparse.Namespace) -> PlanRequest:
    """The request in the task file, with the options given beside it."""
    path = Path(args.task)
    if args.steps:
        raise InvalidInputError(
            f"{args.steps[0][0]} does not combine with --task: the task file "
            "holds its targets, dwells, palm directions and hand actions",
            field=args.steps[0][0][2:],
        )
    try:
        text = without_byte_order_mark(read_at_most(path, MAX_TASK_BYTES))
    except OSError as exc:
        raise InvalidInputError(
            f"{path}: cannot read the task ({exc.strerror})", field="task"
        ) from None
    try:
        check_keys_once(text, PlanRequest.__name__)
        request = parse(PlanRequest, text)
    except InvalidInputError as exc:
        hint = _demo_task_hint(text)
        raise InvalidInputError(
            f"{path}: {exc.message}{hint}", field=exc.field
        ) from None
    _no_retiming(args, request, path)
    fields, how = request.model_dump(), _how(args)
    if args.arm is not None and not _names_an_arm(request):
        fields["arm"] = Side.parse(args.arm)  # the file names none: --arm does
        if request.wrist_path is not None:
            fields["wrist_path"]["arm"] = fields["arm"]
    elif args.arm is not None and Side.parse(args.arm) is not request.arm:
        raise InvalidInputError(
            f"--arm {args.arm} but the task {path} is for the {request.arm.value} arm",
            field="arm",
        )
    for part in ("measures", "limits"):  # the task's others stay
        if part in how:
            how[part] = (fields[part] or {}) | how[part]
    return parse(PlanRequest, fields | how)


def _demo_task_hint(text: bytes) -> str:
    """A pointer to ``armplan demo --task`` when the file is a demo task.

    A demo task (``armplan/demo/handover_task.json``) holds ``phases`` of
    targets; ``plan --task`` takes one ``PlanRequest``.
    """
    try:
        fields = json.loads(text)
    except (ValueError, RecursionError):  # read as "not valid JSON" already
        return ""
    if isinstance(fields, dict) and "phases" in fields:
        return (
            " (this file holds phases: it is a demo task, for "
            "`armplan demo --task FILE`; `plan --task` takes one PlanRequest)"
        )
    return ""


def _names_an_arm(request: PlanRequest) -> bool:
    """Whether the task file names its arm, itself or on its wrist path.

    A path's arm is the request's (``PlanRequest`` checks they agree).
    """
    path = request.wrist_path
    named_path = path is not None and "arm" in path.model_fields_set
    return "arm" in request.model_fields_set or named_path


def _finite(values: Any, name: str) -> Any:
    """``values`` (a number or a list) if every number is finite."""
    numbers = values if isinstance(values, list) else [values]
    if all(math.isfinite(v) for v in numbers):
        return values
    shown = " ".join(f"{v:g}" for v in numbers)
    raise InvalidInputError(
        f"{name} ({shown}) holds a value that is not a finite number",
        field=name.split()[0].removeprefix("--"),
    )
