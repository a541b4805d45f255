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


def reach_advice(arm: ArmModel, target: Sequence[float] | np.ndarray) -> str:
    """The likely fix for ``target`` [m], shape (3,), out of ``arm``'s reach, or "".

    Args:
        arm: The arm asked for.
        target: The wrist target in the torso frame [m], shape (3,); out of
            the arm's reach (not checked).
    """
    point = [float(v) for v in target]
    found = _unit_within_reach(arm, point)
    if found is not None:
        unit, size, scaled = found
        return (
            f"positions are in metres; it looks like {unit}: "
            f"{_shown(scaled)} m is within reach (divide by {round(1 / size)})"
        )
    other = Side.LEFT if arm.side is Side.RIGHT else Side.RIGHT
    if within_reach(load_arm(other), point):
        mirror = [point[0], -point[1], point[2]]
        return (
            f"it is within the {other.value} arm's reach (torso frame: y points "
            f"to NAO's left); ask for the {other.value} arm, or for the "
            f"{arm.side.value} arm at its mirror image {_shown(mirror)} m"
        )
    return ""


def _unit_within_reach(
    arm: ArmModel, point: list[float]
) -> tuple[str, float, list[float]] | None:
    """The unit ``point`` looks written in, its size [m] and ``point`` in m.

    Only a point that, read in that unit, is within reach and at least
    ``NEAREST_TARGET`` from the torso's centre: (12, -13, 5) read in
    millimetres is within the shell of reach too, but inside NAO's chest.
    """
    for unit, size in UNITS:
        scaled = [v * size for v in point]
        if math.hypot(*scaled) >= NEAREST_TARGET and within_reach(arm, scaled):
            return unit, size, scaled
    return None


def within_reach(arm: ArmModel, point: Sequence[float]) -> bool:
    """Whether ``point`` [m], shape (3,), is within ``arm``'s shell of reach."""
    low, high = arm.reach
    return low <= math.dist(point, _shoulder(arm)) <= high


def _shoulder(arm: ArmModel) -> np.ndarray:
    """The arm's shoulder in the torso frame [m], shape (3,)."""
    return arm.fk(rest(arm.side)).shoulder


def _shown(point: Sequence[float]) -> str:
    """``point`` [m] as ``(0.12, -0.13, 0.05)``."""
    return "(" + ", ".join(f"{v:.4g}" for v in point) + ")"


__all__ = ["reach_advice", "within_reach"]
