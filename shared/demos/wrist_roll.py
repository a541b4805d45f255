"""The forearm's roll: the palm's angle about the forearm, from the arm plane.

The paper gives each node an orientation attribute relative to the node
before it (Section II.A); the wrist's is its roll about the forearm relative
to the elbow's frame. Measured here from the arm plane: the angle, about the
forearm axis f, from -n (n = u x f the arm plane's normal, u the upper arm)
to the palm normal. Only differences of this angle within one arm are used.
"""

from __future__ import annotations

import numpy as np

from shared.demos.rotations import FloatArray, unit


def forearm_roll(
    shoulder: FloatArray, elbow: FloatArray, wrist: FloatArray, wrist_frame: FloatArray
) -> FloatArray:
    """Roll of the palm about the forearm [rad], shape (n,).

    Args:
        shoulder: Shoulder positions [m], shape (n, 3).
        elbow: Elbow positions [m], shape (n, 3).
        wrist: Wrist positions [m], shape (n, 3).
        wrist_frame: Wrist frames (x forearm, y palm normal of a right hand),
            shape (n, 3, 3).
    """
    fore = unit(wrist - elbow)
    away = -unit(np.cross(elbow - shoulder, fore))
    side = np.cross(fore, away)
    palm = wrist_frame[:, :, 1]
    return np.arctan2(
        np.einsum("ij,ij->i", palm, side), np.einsum("ij,ij->i", palm, away)
    )


def roll_to_go(
    shoulder: FloatArray, elbow: FloatArray, wrist: FloatArray, wrist_frame: FloatArray
) -> FloatArray:
    """Roll still to make to end as at the last sample [rad], in [-pi, pi], (n,)."""
    roll = forearm_roll(shoulder, elbow, wrist, wrist_frame)
    return np.asarray(np.angle(np.exp(1j * (roll[-1] - roll))), dtype=float)
