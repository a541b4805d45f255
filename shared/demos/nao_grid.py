"""The paper's 16 grid points on NAO, for the average subject.

Each point is the wrist position (and palm direction) at the end of the
reach model's noise-free reach (``reach_model``) of a subject of average
stature, retargeted to NAO (``retarget``), with that reach's duration: the
targets NAO reaches in the Table-4-like experiment.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from shared.demos.anthropometry import (
    STATURE_MEN,
    STATURE_WOMEN,
    subject_from_stature,
)
from shared.demos.arm_pose import chain_points
from shared.demos.grid import grid_targets
from shared.demos.reach_model import AVERAGE_STYLE, plan_reach
from shared.demos.retarget import ArmTrack, nao_arm_size, retarget
from shared.demos.rotations import FloatArray
from shared.robot.side import Side

#: Stature of the average subject [m]: the mean of the men's and women's.
AVERAGE_STATURE = 0.5 * (STATURE_MEN[0] + STATURE_WOMEN[0])
_MIRROR = np.array([1.0, -1.0, 1.0])


class GridTarget(NamedTuple):
    """One grid point on NAO.

    Attributes:
        point: Its number, 1..16.
        wrist: Wrist target in NAO's torso frame [m], shape (3,).
        palm: Palm direction at the end of the human reach (unit), shape (3,).
        duration: The average subject's movement time [s].
    """

    point: int
    wrist: FloatArray
    palm: FloatArray
    duration: float


def nao_grid(side: Side | str = Side.RIGHT) -> list[GridTarget]:
    """The 16 grid points retargeted to NAO's ``side`` arm, P1 first."""
    side = Side.parse(side)
    person = subject_from_stature("average", AVERAGE_STATURE)
    size = nao_arm_size(side)
    mirror = np.ones(3) if side is Side.RIGHT else _MIRROR
    out = []
    for index, target in enumerate(grid_targets(person.arm_length)):
        plan = plan_reach(person, AVERAGE_STYLE, target)
        end = chain_points(
            plan.goal.frame[None],
            np.array([plan.goal.flexion]),
            np.array([plan.goal.roll]),
            person.upper_arm,
            person.forearm,
        )
        human = ArmTrack(np.zeros((1, 3)), end.elbow * mirror, end.wrist * mirror)
        wrist = retarget(human, size).wrist[0]
        palm = end.wrist_frame[0][:, 1] * mirror
        out.append(GridTarget(index + 1, wrist, palm, plan.duration))
    return out
