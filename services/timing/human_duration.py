"""How long a person takes for a reach, scaled to NAO: the default duration.

Table 4 of the paper: the mean time grows with the distance from the hand's
start to the point (0.55-1.01 s). With the grid placed as in
:mod:`services.timing.paper_grid`, a power law of the distance d over the arm
length L fits it (least squares on the logarithms, :func:`fit_table4`):

    T = DURATION_SCALE * (d / L) ** DURATION_EXPONENT
      = 0.685 s * (d / L) ** 1.359          (RMS residual 0.065 s)

A power law through the origin, not a line: a line fits as well but reaches
zero at d = 0.27 L and would give short moves no time at all. Durations
below ``MIN_DURATION`` are raised to it (small corrections still take a
human fraction of a second).

Scaling to NAO: NAO's arm has other proportions (upper arm 0.106 m, forearm
0.056 m), so d / L is not the same on NAO for "the same" reach. Human
movements are retargeted to NAO by keeping the directions of upper arm and
forearm (SPEC); :func:`reach_duration` undoes that: it takes the directions
of NAO's upper arm and forearm at the start and at the goal, rebuilds the
wrist of a human arm with those directions, and feeds the human distance to
the law. So NAO reaching a retargeted point takes the time the person took.
"""

from __future__ import annotations

import numpy as np

from services.timing import paper_grid
from shared.robot.arm_model import ArmModel, ArmPoints

#: Duration of a reach one arm length long [s] (fitted to Table 4).
DURATION_SCALE = 0.685
#: Growth of the duration with the distance (fitted to Table 4).
DURATION_EXPONENT = 1.359
#: Shortest default duration [s].
MIN_DURATION = 0.3


def human_duration(distance_ratio: float) -> float:
    """A person's reach time [s] for a start-to-goal distance over arm length."""
    ratio = max(float(distance_ratio), 0.0)
    return max(MIN_DURATION, DURATION_SCALE * ratio**DURATION_EXPONENT)


def fit_table4() -> tuple[float, float]:
    """(scale [s], exponent) of the power law fitted to Table 4 on the grid."""
    exponent, log_scale = np.polyfit(
        np.log(paper_grid.grid_distances()), np.log(paper_grid.TABLE4_TIMES), 1
    )
    return float(np.exp(log_scale)), float(exponent)


def human_wrist(points: ArmPoints) -> np.ndarray:
    """Wrist of a human arm with NAO's arm directions, from the shoulder [m], (3,).

    Upper arm along NAO's shoulder-to-elbow line, forearm along its
    elbow-to-wrist line, with the human lengths of :mod:`paper_grid`.
    """
    upper = points.elbow - points.shoulder
    fore = points.wrist - points.elbow
    return paper_grid.UPPER_ARM * upper / np.linalg.norm(
        upper
    ) + paper_grid.FOREARM * fore / np.linalg.norm(fore)


def human_distance_ratio(
    arm: ArmModel, q_start: np.ndarray, q_goal: np.ndarray
) -> float:
    """Start-to-goal wrist distance of the retargeted human arm over its length."""
    start = human_wrist(arm.fk(np.asarray(q_start, dtype=float)))
    goal = human_wrist(arm.fk(np.asarray(q_goal, dtype=float)))
    return float(np.linalg.norm(goal - start)) / paper_grid.ARM_LENGTH


def reach_duration(arm: ArmModel, q_start: np.ndarray, q_goal: np.ndarray) -> float:
    """Default duration [s] of NAO's move from posture ``q_start`` to ``q_goal``.

    Args:
        arm: The arm.
        q_start: Posture at the start [rad], shape (5,).
        q_goal: Posture at the goal [rad], shape (5,).
    """
    return human_duration(human_distance_ratio(arm, q_start, q_goal))


__all__ = [
    "DURATION_EXPONENT",
    "DURATION_SCALE",
    "MIN_DURATION",
    "fit_table4",
    "human_distance_ratio",
    "human_duration",
    "human_wrist",
    "reach_duration",
]
