"""The wrist path of one reach of a task, as a message."""

from __future__ import annotations

import numpy as np

from services.planner.wrist_path import reach_path
from services.timing.human_duration import human_duration
from shared.messages import ReachTarget, WristPath
from shared.robot.arm_model import ArmModel

#: Path points per second of the reach's nominal (human) duration [Hz]: the
#: paper's 100 Hz.
PATH_RATE = 100.0


def reach_wrist_path(
    arm: ArmModel, start_q: np.ndarray, target: ReachTarget, rate: float = PATH_RATE
) -> WristPath:
    """A human-like wrist path from where ``start_q`` puts the wrist to ``target``.

    Its points are ``rate`` a second of the reach's estimated human duration
    (the hand's distance over the arm's length, Table 4's law), so a reach
    of about one second has about 100 points; the timing stage later sets
    the actual pace.

    Args:
        arm: The arm.
        start_q: Posture at the start [rad], shape (5,).
        target: The reach's goal (position, optional palm direction).
        rate: Points per second of the nominal duration [Hz].
    """
    goal = np.array(target.position)
    length = arm.upper_arm_length + arm.forearm_length
    hand = float(np.linalg.norm(goal - arm.fk(start_q).wrist))
    nominal = human_duration(hand / length)
    path = reach_path(arm, start_q, goal, nominal, rate)
    return WristPath(
        arm=arm.side,
        times=path.times.tolist(),
        positions=[tuple(p) for p in path.positions.tolist()],
        palm=target.palm,
    )
