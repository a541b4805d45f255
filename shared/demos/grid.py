"""The paper's 16 targets: a 4 x 4 grid, 10 cm apart, in front of the shoulder.

The paper (Section V.A, Fig. 12) has each subject reach 16 points on a board,
4 rows and 4 columns 10 cm apart, starting with the arm hanging. It does not
give the board's place; here it stands in front of the right shoulder at
``BOARD_DISTANCE`` times the subject's arm length (so every subject reaches
every point with the elbow bent 35-85 degrees), its columns centred on the
shoulder and its rows from 25 cm below to 5 cm above shoulder height.

Points are numbered row by row from the bottom, each row from the body's
midline outwards: P1..P4 is the lowest row (nearest the hanging hand, the
shortest reaches, as in the paper's Table 4), P13..P16 the highest.

Positions are in the subject's shoulder frame: origin at the shoulder joint
centre, x forward, y to the left, z up (the axes of NAO's torso frame).
"""

from __future__ import annotations

import numpy as np
import numpy.typing as npt

#: Distance of the board in front of the shoulder, as a fraction of L_u + L_f.
BOARD_DISTANCE = 0.75
#: Spacing of the grid [m] (human scale).
SPACING = 0.10
#: Heights of the four rows relative to the shoulder, bottom first [m].
ROW_HEIGHTS = (-0.25, -0.15, -0.05, 0.05)
#: Lateral positions of the four columns, midline first, for a right arm [m].
COLUMN_OFFSETS = (0.15, 0.05, -0.05, -0.15)
#: Number of points.
POINTS = 16


def grid_targets(arm_length: float, sign: float = 1.0) -> npt.NDArray[np.float64]:
    """The 16 targets in the shoulder frame [m], shape (16, 3), P1 first.

    Args:
        arm_length: The subject's L_u + L_f [m].
        sign: +1 for the right arm, -1 for the left (mirrors y).
    """
    rows = [
        (BOARD_DISTANCE * arm_length, sign * y, z)
        for z in ROW_HEIGHTS
        for y in COLUMN_OFFSETS
    ]
    return np.array(rows, dtype=float)


def point_name(index: int) -> str:
    """``"P1"`` .. ``"P16"`` for index 0 .. 15."""
    return f"P{index + 1}"
