"""The paper's similarity experiment in human scale: grid, start, and Table 4.

The paper (Section V.A) has subjects reach 16 points of a 4 x 4 grid, 10 cm
apart, from the arm hanging down, and Table 4 gives the mean time per point
(0.55-1.01 s). It does not give the grid's place; these assumptions put it
where Table 4's times and the text agree:

- Body: a 1.70 m adult with Winter's segment proportions (Winter, *Biomechanics
  and Motor Control of Human Movement*, 4th ed., 2009): upper arm 0.186 H,
  forearm 0.146 H, so shoulder to wrist 0.564 m. The reaching point is the
  wrist (the hand's offset beyond it shifts every distance alike).
- Start: the arm hanging straight down, wrist 0.564 m below the shoulder.
- Grid: a vertical plane 0.30 m in front of the shoulder. Rows 1-4 (P1-P4
  ... P13-P16) at 0.20 m below, 0.10 m below, level with and 0.10 m above
  the shoulder: the paper calls rows 3-4 "high rows", and Table 4's times
  grow row by row. Columns 1-4 from 0.30 m towards the body's midline to in
  line with the shoulder: in the low rows, column 1 takes longest and column
  4 shortest.

Coordinates are relative to the shoulder: x forward, y towards the midline,
z up [m].
"""

from __future__ import annotations

import numpy as np

from shared.robot.arm_model import ArmModel

#: Table 4: mean time per point P1..P16 [s].
TABLE4_TIMES = np.array(
    [
        *(0.72, 0.58, 0.60, 0.55),  # row 1: P1-P4
        *(0.80, 0.74, 0.57, 0.55),  # row 2: P5-P8
        *(0.94, 0.94, 0.93, 0.92),  # row 3: P9-P12
        *(1.01, 0.99, 0.93, 0.98),  # row 4: P13-P16
    ]
)
#: Body height of the modelled subject [m].
HEIGHT = 1.70
#: Upper arm and forearm length [m] (Winter 2009: 0.186 H and 0.146 H).
UPPER_ARM, FOREARM = 0.186 * HEIGHT, 0.146 * HEIGHT
#: Shoulder-to-wrist length of the straight arm [m].
ARM_LENGTH = UPPER_ARM + FOREARM
#: Distance of the grid plane in front of the shoulder [m].
GRID_FORWARD = 0.30
#: Heights of rows 1-4 relative to the shoulder [m].
ROW_HEIGHTS = np.array([-0.20, -0.10, 0.0, 0.10])
#: Offsets of columns 1-4 towards the midline [m].
COLUMN_OFFSETS = np.array([0.30, 0.20, 0.10, 0.0])


def grid_points() -> np.ndarray:
    """P1..P16 relative to the shoulder [m], shape (16, 3), row by row."""
    rows, columns = np.meshgrid(ROW_HEIGHTS, COLUMN_OFFSETS, indexing="ij")
    forward = np.full(16, GRID_FORWARD)
    return np.column_stack((forward, columns.ravel(), rows.ravel()))


def hanging_wrist() -> np.ndarray:
    """The wrist at the start, arm hanging, relative to the shoulder [m], (3,)."""
    return np.array([0.0, 0.0, -ARM_LENGTH])


def grid_distances() -> np.ndarray:
    """Start-to-point distance of P1..P16 over the arm length, shape (16,)."""
    return np.linalg.norm(grid_points() - hanging_wrist(), axis=1) / ARM_LENGTH


def elbow_down_posture(point: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Unit directions of upper arm and forearm reaching ``point`` (3,), elbow down.

    The human posture for a grid point: the arm triangle fixes the elbow's
    bend, and the elbow hangs below the shoulder-wrist line (the relaxed
    swivel angle), which is what retargeting to NAO keeps.
    """
    distance = float(np.linalg.norm(point))
    axis = point / distance
    cos_bend = (UPPER_ARM**2 + distance**2 - FOREARM**2) / (2 * UPPER_ARM * distance)
    angle = np.arccos(np.clip(cos_bend, -1.0, 1.0))
    down = np.array([0.0, 0.0, -1.0])
    side = down - axis * (down @ axis)
    side /= np.linalg.norm(side)
    elbow = UPPER_ARM * (np.cos(angle) * axis + np.sin(angle) * side)
    return elbow / UPPER_ARM, (point - elbow) / FOREARM


def nao_targets(arm: ArmModel) -> np.ndarray:
    """P1..P16 retargeted to NAO's wrist, torso frame [m], shape (16, 3).

    Upper arm and forearm keep the directions of the elbow-down human
    posture and take NAO's lengths (SPEC); where NAO's elbow cannot bend as
    far as the person's (it stops at 88.5 degrees), the point is moved along
    the shoulder-wrist line into NAO's reach, 1 mm inside its bounds. The
    left arm mirrors the grid (y changes sign).
    """
    shoulder = arm.fk(np.zeros(5)).shoulder
    mirror = np.array([1.0, arm.side.sign, 1.0])  # y towards the midline
    near, far = arm.reach[0] + 1e-3, arm.reach[1] - 1e-3
    out = np.empty((16, 3))
    for k, point in enumerate(grid_points()):
        upper, fore = elbow_down_posture(point)
        wrist = arm.upper_arm_length * upper + arm.forearm_length * fore
        distance = float(np.linalg.norm(wrist))
        out[k] = shoulder + mirror * wrist * np.clip(distance, near, far) / distance
    return out


__all__ = [
    "ARM_LENGTH",
    "FOREARM",
    "TABLE4_TIMES",
    "UPPER_ARM",
    "elbow_down_posture",
    "grid_distances",
    "grid_points",
    "hanging_wrist",
    "nao_targets",
]
