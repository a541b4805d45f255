"""The palm direction and the hand's roll about the forearm.

NAO's wrist has one joint, WristYaw, turning the hand about the forearm axis
(the wrist frame's x axis). With five joints the wrist's orientation task is
therefore one-dimensional: the roll about the forearm that turns the palm
towards a wanted direction. At zero joint angles NAO's palms face each other,
so the palm normal is the wrist frame's +y axis on the right hand and -y on
the left.

Written on plain indexing (rotation as rows r[i][j]) so that it serves numpy
arrays and the IK's float tuples alike.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any, Final

import numpy as np

#: Below this length of the wanted palm direction projected off the forearm
#: axis, roll cannot change how well the palm faces it (palm along forearm).
DEGENERATE: Final = math.sin(math.radians(5.0))


def palm_normal(wrist_rotation: np.ndarray, sign: float) -> np.ndarray:
    """The palm's normal in the torso frame, unit, shape (3,).

    Args:
        wrist_rotation: Orientation of the wrist frame, shape (3, 3).
        sign: +1 for the right hand, -1 for the left.
    """
    return sign * np.asarray(wrist_rotation)[:, 1]


def roll_error(
    wrist_rotation: Any, sign: float, palm: Sequence[float] | np.ndarray
) -> float:
    """Roll about the forearm that best turns the palm towards ``palm`` [rad].

    Positive about the forearm axis (wrist frame x). Zero when ``palm`` lies
    within 5 degrees of the forearm axis, where roll does not matter.

    Args:
        wrist_rotation: Orientation of the wrist frame, 3x3 (rows r[i][j]).
        sign: +1 for the right hand, -1 for the left.
        palm: Wanted palm direction, unit, 3 values.
    """
    r = wrist_rotation
    ax, ay, az = float(r[0][0]), float(r[1][0]), float(r[2][0])
    nx, ny, nz = sign * float(r[0][1]), sign * float(r[1][1]), sign * float(r[2][1])
    px, py, pz = float(palm[0]), float(palm[1]), float(palm[2])
    along = px * ax + py * ay + pz * az
    wx, wy, wz = px - along * ax, py - along * ay, pz - along * az
    length = math.sqrt(wx * wx + wy * wy + wz * wz)
    if length < DEGENERATE:
        return 0.0
    # axis . (normal x wanted), normal . wanted (the length cancels in atan2)
    cx, cy, cz = ny * wz - nz * wy, nz * wx - nx * wz, nx * wy - ny * wx
    return math.atan2(ax * cx + ay * cy + az * cz, nx * wx + ny * wy + nz * wz)


def roll_rate(
    wrist_rotation: Any, sign: float, palm: Sequence[float]
) -> tuple[float, float, float]:
    """How fast the hand gains the roll :func:`roll_error` asks for [rad/rad].

    The exact derivative: turning the wrist frame at angular velocity
    ``u`` (unit axis, torso frame) changes ``roll_error`` by ``-u . g`` per
    radian, and this returns ``g``. Along the forearm axis ``u . g`` is 1;
    about other axes the forearm itself swings relative to ``palm``, which
    the projection on the forearm axis alone leaves out.

    With ``b = a x n`` (forearm axis ``a``, palm normal ``n``), the roll is
    ``atan2(p . b, p . n)``, and turning by ``u`` moves ``n`` and ``b`` by
    ``u x n`` and ``u x b``, so ``g = -((p.n) b - (p.b) n) x p / ((p.n)^2 +
    (p.b)^2)``. Where ``palm`` lies within 5 degrees of the forearm axis
    (:data:`DEGENERATE`, the roll error is 0 there) ``g`` is the forearm axis.

    Args:
        wrist_rotation: Orientation of the wrist frame, 3x3 (rows r[i][j]).
        sign: +1 for the right hand, -1 for the left.
        palm: Wanted palm direction, unit, 3 values.

    Returns:
        g, 3 floats: d(roll made)/dq_k is ``axis_k . g`` for joint axis k.
    """
    r = wrist_rotation
    ax, ay, az = float(r[0][0]), float(r[1][0]), float(r[2][0])
    nx, ny, nz = sign * float(r[0][1]), sign * float(r[1][1]), sign * float(r[2][1])
    px, py, pz = float(palm[0]), float(palm[1]), float(palm[2])
    bx, by, bz = ay * nz - az * ny, az * nx - ax * nz, ax * ny - ay * nx
    x = px * nx + py * ny + pz * nz
    y = px * bx + py * by + pz * bz
    off = x * x + y * y
    if off < DEGENERATE * DEGENERATE:
        return ax, ay, az
    # m = x b - y n; g = -(m x p) / off = (p x m) / off
    mx, my, mz = x * bx - y * nx, x * by - y * ny, x * bz - y * nz
    return (
        (py * mz - pz * my) / off,
        (pz * mx - px * mz) / off,
        (px * my - py * mx) / off,
    )
