"""What to change about a target out of the arm's reach, when the mistake is plain.

Two mistakes put a lab's target out of reach, where the reach error alone
("183.7513 m from the right shoulder") leaves the user to find them:

- units: a target written in millimetres or centimetres, (120, -130, 50),
  which divided by 1000 or 100 is within reach;
- the arm: a target within the other arm's reach, (0.12, 0.13, 0.05) for
  the right arm (the torso frame's y points to NAO's left), or a right-arm
  target mirrored for the left arm in its own frame.

:func:`reach_advice` names the fix, or says nothing.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

from shared.robot.arm_model import ArmModel, load_arm
from shared.robot.postures import rest
from shared.robot.side import Side

#: Units a target may have been written in by mistake, and their size [m].
UNITS = (("millimetres", 1e-3), ("centimetres", 1e-2))
#: Least distance from the torso's centre of a target read in other units
#: [m]: nearer, the wrist would be inside NAO's chest.
NEAREST_TARGET = 0.1


def reach_advice(
    arm: ArmModel,
    target: Sequence[float] | np.ndarray,
    path: Sequence[Sequence[float]] | np.ndarray | None = None,
) -> str:
    """The likely fix for ``target`` [m], shape (3,), out of ``arm``'s reach, or "".

    Args:
        arm: The arm asked for.
        target: The wrist target in the torso frame [m], shape (3,); out of
            the arm's reach (not checked).
        path: Every position of the wrist path ``target`` is a sample of
            [m], shape (n, 3), or None for a lone target: the fix is named
            only if it fits every sample (a path in metres with one sample
            mistyped 120 is not in millimetres; one crossing the midline is
            not the other arm's).
    """
    point = np.asarray(target, dtype=float)
    points = point[np.newaxis] if path is None else np.asarray(path, dtype=float)
    for unit, size in UNITS:
        if _all_fit(arm, points * size):
            return (
                f"positions are in metres; it looks like {unit}: "
                f"{_shown(point * size)} m is within reach "
                f"(divide by {round(1 / size)})"
            )
    other = load_arm(Side.LEFT if arm.side is Side.RIGHT else Side.RIGHT)
    if _all_fit(other, points):
        instead = (
            f"at its mirror image {_shown(point * (1.0, -1.0, 1.0))} m"
            if path is None
            else "with every y negated"
        )
        return (
            f"it is within the {other.side.value} arm's reach (torso frame: y "
            f"points to NAO's left); ask for the {other.side.value} arm, or for "
            f"the {arm.side.value} arm {instead}"
        )
    return ""


def _all_fit(arm: ArmModel, points: np.ndarray) -> bool:
    """Whether every point [m], shape (n, 3), is in reach and outside the chest.

    At least ``NEAREST_TARGET`` from the torso's centre: (12, -13, 5) read
    in millimetres is within the shell of reach too, and (0, -0.05, 0.05)
    is within the left arm's, but both are inside NAO's chest.
    """
    low, high = arm.reach
    with np.errstate(over="ignore", invalid="ignore"):  # 1e308 is out
        distance = np.linalg.norm(points - _shoulder(arm), axis=1)
        centre = np.linalg.norm(points, axis=1)
    return bool(
        np.all((centre >= NEAREST_TARGET) & (low <= distance) & (distance <= high))
    )


def within_reach(arm: ArmModel, point: Sequence[float]) -> bool:
    """Whether ``point`` [m], shape (3,), is within ``arm``'s shell of reach."""
    low, high = arm.reach
    return low <= math.dist(point, _shoulder(arm)) <= high


def _shoulder(arm: ArmModel) -> np.ndarray:
    """The arm's shoulder in the torso frame [m], shape (3,)."""
    return arm.fk(rest(arm.side)).shoulder


def _shown(point: Sequence[float] | np.ndarray) -> str:
    """``point`` [m] as ``(0.12, -0.13, 0.05)``."""
    return "(" + ", ".join(f"{v:.4g}" for v in point) + ")"


__all__ = ["reach_advice", "within_reach"]
