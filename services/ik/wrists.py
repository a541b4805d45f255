"""Wrist positions of many postures at once (forward kinematics on arrays).

The same chain as ``services.ik.kernel.chain.Chain.state`` (each joint's
origin in its parent, turned about a principal axis), evaluated for every
posture of an array together, for the wrist only: what a trajectory's
samples need, hundreds of postures per plan.
"""

from __future__ import annotations

import numpy as np

from services.ik.kernel.chain import Chain

#: The other two axes of each principal axis (x: y, z; y: z, x; z: x, y).
_PLANE = {0: (1, 2), 1: (2, 0), 2: (0, 1)}


def wrist_positions(chain: Chain, q: np.ndarray) -> np.ndarray:
    """Wrist positions [m], shape (n, 3), of postures ``q`` [rad], shape (n, 5).

    The wrist is the origin of the fifth joint (WristYaw), so the first four
    angles set it.
    """
    angles = np.asarray(q, dtype=float).reshape(-1, 5)
    n = len(angles)
    columns = [np.zeros((n, 3)) for _ in range(3)]
    for axis, column in enumerate(columns):
        column[:, axis] = 1.0
    wrist = np.zeros((n, 3))
    for k in range(5):
        wrist += sum(c * v for c, v in zip(columns, chain.offsets[k], strict=True))
        if k == 4:
            break
        a, b = _PLANE[chain.axis_index[k]]
        c, s = np.cos(angles[:, k])[:, None], np.sin(angles[:, k])[:, None]
        columns[a], columns[b] = (
            columns[a] * c + columns[b] * s,
            columns[b] * c - columns[a] * s,
        )
    return wrist
