"""Reference postures of the NAO arm, and mirroring between arms."""

from __future__ import annotations

import math

import numpy as np

from shared.robot.side import Side

#: Sign change from a right-arm posture to the mirrored left-arm posture:
#: the pitch joint keeps its sign, the roll and yaw joints flip.
MIRROR = np.array([1.0, -1.0, -1.0, -1.0, -1.0])

#: Right arm hanging at rest, as in the paper's protocol [rad]: upper arm
#: vertical and slightly abducted, elbow slightly bent forward, wrist neutral.
_REST_RIGHT = (math.pi / 2, -0.10, math.pi / 2, 0.20, 0.0)

#: Right arm stretched forward horizontally, the handover experiment's start [rad].
_FORWARD_RIGHT = (0.0, -0.05, math.pi / 2, 0.05, 0.0)


def mirror(q: np.ndarray) -> np.ndarray:
    """The posture of the other arm that mirrors ``q`` [rad], shape (..., 5)."""
    return np.asarray(q, dtype=float) * MIRROR


def _for(side: Side, right: tuple[float, ...]) -> np.ndarray:
    q = np.array(right)
    return q if side is Side.RIGHT else mirror(q)


def rest(side: Side | str) -> np.ndarray:
    """The arm hanging at rest [rad], shape (5,)."""
    return _for(Side.parse(side), _REST_RIGHT)


def forward(side: Side | str) -> np.ndarray:
    """The arm stretched forward horizontally [rad], shape (5,)."""
    return _for(Side.parse(side), _FORWARD_RIGHT)
